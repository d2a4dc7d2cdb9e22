#include "core/linear/CholeskyPreconditioner.h"

#include "core/linear/PermutedValues.h"

#include "core/forces/SimdPath.h"
#include "core/parallel/TaskPool.h"

#include <algorithm>
#include <cmath>

namespace masse
{
namespace
{
// One copy of each triangular solve per SIMD path: only the instruction set differs (see SimdPath.h for why the bits
// do not).
#define MASSE_TRIANGULAR_KERNELS(suffix, targetAttribute, dot)                                                         \
    /* L y = b in place on y over factor rows [begin, end), from the first row up: y_i -= sum over L's row i. */       \
    targetAttribute void forwardRows##suffix(const RunLengthRows::View& rows, float* y, Eigen::Index begin,            \
                                             Eigen::Index end)                                                         \
    {                                                                                                                  \
        for (Eigen::Index i = begin; i < end; ++i)                                                                     \
        {                                                                                                              \
            y[i] -= dot(rows, i, y);                                                                                   \
        }                                                                                                              \
    }                                                                                                                  \
    /* D L^T x = y in place on x over factor rows [begin, end), from the last row down: x_j = y_j / d_j - sum over     \
       L's column j of L_ij x_i, column j being row n-1-j of `columns`. */                                             \
    targetAttribute void backwardRows##suffix(const RunLengthRows::View& columns, const float* d, float* x,            \
                                              Eigen::Index n, Eigen::Index begin, Eigen::Index end)                    \
    {                                                                                                                  \
        for (Eigen::Index q = n - end; q < n - begin; ++q)                                                             \
        {                                                                                                              \
            const Eigen::Index column = n - 1 - q;                                                                     \
            x[column] = x[column] / d[column] - dot(columns, q, x);                                                    \
        }                                                                                                              \
    }

// The AVX-512 path adds a run's last few entries under a mask (rowDotAvx512); the AVX2 path reads the halves with
// F16C's instruction, the default one in software, both exact.
[[gnu::always_inline]] inline float rowDotDefault(const RunLengthRows::View& m, Eigen::Index row, const float* x)
{
    return rowDot(m, row, x, floatFromHalf);
}
#if defined(__x86_64__) && defined(__GNUC__)
[[gnu::always_inline]] inline __attribute__((target("avx2,f16c"))) float rowDotAvx2(const RunLengthRows::View& m,
                                                                                    Eigen::Index row, const float* x)
{
    return rowDot(
        m, row, x, [](std::uint16_t half) __attribute__((target("avx2,f16c"))) { return _cvtsh_ss(half); });
}
#endif
MASSE_TRIANGULAR_KERNELS(Default, , rowDotDefault)
#if defined(__x86_64__) && defined(__GNUC__)
MASSE_TRIANGULAR_KERNELS(Avx2, __attribute__((target("avx2,f16c"))), rowDotAvx2)
MASSE_TRIANGULAR_KERNELS(Avx512, __attribute__((target("avx512f"))), rowDotAvx512)
#endif
#undef MASSE_TRIANGULAR_KERNELS

void forwardRowsOn(SimdPath path, const RunLengthRows::View& rows, float* y, Eigen::Index begin, Eigen::Index end)
{
    switch (path)
    {
#if defined(__x86_64__) && defined(__GNUC__)
    case SimdPath::Avx512:
        return forwardRowsAvx512(rows, y, begin, end);
    case SimdPath::Avx2:
        return forwardRowsAvx2(rows, y, begin, end);
#endif
    default:
        return forwardRowsDefault(rows, y, begin, end);
    }
}

void backwardRowsOn(SimdPath path, const RunLengthRows::View& columns, const float* d, float* x, Eigen::Index n,
                    Eigen::Index begin, Eigen::Index end)
{
    switch (path)
    {
#if defined(__x86_64__) && defined(__GNUC__)
    case SimdPath::Avx512:
        return backwardRowsAvx512(columns, d, x, n, begin, end);
    case SimdPath::Avx2:
        return backwardRowsAvx2(columns, d, x, n, begin, end);
#endif
    default:
        return backwardRowsDefault(columns, d, x, n, begin, end);
    }
}
} // namespace

void CholeskyPreconditioner::analyse(const SparseMatrix& a, const DissectionOrder& dissection)
{
    const std::vector<Index>& massOrder = dissection.order;
    m_stages.clear();
    for (const std::vector<OrderRange>& stage : dissection.stages)
    {
        m_stages.emplace_back();
        for (const OrderRange& range : stage)
        {
            m_stages.back().push_back({3 * range.begin, 3 * range.end});
        }
    }
    m_permutation.resize(a.rows());
    for (std::size_t position = 0; position < massOrder.size(); ++position)
    {
        for (int c = 0; c < 3; ++c)
        {
            m_permutation.indices()[Eigen::Index(3 * massOrder[position]) + c] =
                SparseMatrix::StorageIndex(3 * position) + c;
        }
    }
    m_permutedSources = findPermutedSources(
        a,
        [&](const SparseMatrix& m)
        {
            SparseMatrix full;
            full = m.selfadjointView<Eigen::Lower>().twistedBy(m_permutation);
            return full;
        },
        m_permutedMatrix);
    gatherPermutedValues(a, m_permutedSources, m_permutedMatrix);
    m_factor.analyse(m_permutedMatrix, m_stages);
    m_ready = false;
    m_copiesLaidOut = false;
    m_filtered.resize(a.rows());
    m_permuted.resize(std::size_t(a.rows()));
}

bool CholeskyPreconditioner::refresh(const SparseMatrix& a)
{
    // A refresh (not every step) copies the matrix into the factor's order; the pattern is unchanged.
    gatherPermutedValues(a, m_permutedSources, m_permutedMatrix);
    m_ready = m_factor.factorize(m_permutedMatrix);
    if (m_ready)
    {
        // The two copies of the factor are built at once, one a task. Their runs depend only on the factor's pattern,
        // the analysed one at every refresh: they are laid out at the first refresh, and later ones write the values.
        const Vector& diagonal = m_factor.diagonal();
        m_diagonal.resize(std::size_t(diagonal.size()));
        for (Eigen::Index i = 0; i < diagonal.size(); ++i)
        {
            m_diagonal[std::size_t(i)] = float(diagonal[i]);
        }
        const SparseMatrix& lower = m_factor.lower();
        runChunks(2,
                  [&](std::size_t copy)
                  {
                      if (copy == 0)
                      {
                          m_copiesLaidOut ? m_forward.refillLowerRows(lower) : m_forward.assignLowerRows(lower);
                      }
                      else
                      {
                          m_copiesLaidOut ? m_backward.refillLowerColumnsLastFirst(lower)
                                          : m_backward.assignLowerColumnsLastFirst(lower);
                      }
                  });
        m_copiesLaidOut = true;
    }
    ++m_refreshCount;
    return m_ready;
}

void CholeskyPreconditioner::setFilter(const std::vector<Index>& masses, const std::vector<Mat3>& filters)
{
    m_masses = &masses;
    m_filters = &filters;
}

void CholeskyPreconditioner::apply(const Vector& r, Vector& z) const
{
    const bool filtered = m_masses && !m_masses->empty();
    const Vector* input = &r;
    if (filtered)
    {
        m_filtered = r;
        for (std::size_t k = 0; k < m_masses->size(); ++k)
        {
            const Eigen::Index row = Eigen::Index(3 * (*m_masses)[k]);
            m_filtered.segment<3>(row) = (*m_filters)[k] * r.segment<3>(row);
        }
        input = &m_filtered;
    }
    solveWithFactor(*input, z);
    if (filtered)
    {
        for (std::size_t k = 0; k < m_masses->size(); ++k)
        {
            const Eigen::Index row = Eigen::Index(3 * (*m_masses)[k]);
            const Mat3& s = (*m_filters)[k];
            const Vec3 free = s * z.segment<3>(row);
            z.segment<3>(row) = free + (r.segment<3>(row) - s * r.segment<3>(row));
        }
    }
}

void CholeskyPreconditioner::solveWithFactor(const Vector& b, Vector& x) const
{
    // P^T L D L^T P x = b, spelled out rather than through SimplicialLDLT::solve, whose in-place permutation
    // allocates a mask on every call. Both triangular solves run the ranges of each stage (see DissectionOrder) on the
    // pool, the forward one from the first stage, the backward one from the last, every entry computed by one gather
    // in a fixed order whoever runs it (RunLengthRows::rowDot), so the bits do not depend on the thread count. They run
    // in single precision on the factor's half values (see RunLengthRows); r and z stay double. b is scaled by a power
    // of two to a largest entry in [1, 2) on the way in, and x back on the way out: a float's range is far narrower
    // than a double's, and a residual of 1e-40 or 1e40 would otherwise flush to zero or overflow. A power of two
    // scales every rounding with it, so where nothing would have left the float range the bits are those of no scaling.
    const auto& permutation = m_permutation.indices();
    const Eigen::Index n = b.size();
    const Real largest = b.cwiseAbs().maxCoeff();
    if (!(largest > 0) || !std::isfinite(largest))
    {
        x = b; // zero stays zero; a non-finite residual passes through to the run's finite check
        return;
    }
    const int exponent = std::ilogb(largest);
    const Real down = std::ldexp(Real(1), -exponent);
    const Real up = std::ldexp(Real(1), exponent); // multiplying by it rounds as ldexp would, without a call an entry
    for (Eigen::Index i = 0; i < n; ++i)
    {
        m_permuted[permutation[i]] = float(b[i] * down);
    }
    const SimdPath path = activeSimdPath();
    const RunLengthRows::View forward = m_forward.view();
    const RunLengthRows::View backward = m_backward.view();
    float* work = m_permuted.data();
    for (const std::vector<OrderRange>& ranges : m_stages)
    {
        runChunks(ranges.size(), [&](std::size_t k)
                  { forwardRowsOn(path, forward, work, Eigen::Index(ranges[k].begin), Eigen::Index(ranges[k].end)); });
    }
    for (auto stage = m_stages.rbegin(); stage != m_stages.rend(); ++stage)
    {
        const std::vector<OrderRange>& ranges = *stage;
        runChunks(ranges.size(),
                  [&](std::size_t k)
                  {
                      backwardRowsOn(path, backward, m_diagonal.data(), work, n, Eigen::Index(ranges[k].begin),
                                     Eigen::Index(ranges[k].end));
                  });
    }
    for (Eigen::Index i = 0; i < n; ++i)
    {
        x[i] = Real(m_permuted[permutation[i]]) * up;
    }
}

} // namespace masse
