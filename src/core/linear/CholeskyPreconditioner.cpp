#include "core/linear/CholeskyPreconditioner.h"

#include "core/linear/PermutedValues.h"

#include "core/forces/SimdPath.h"
#include "core/parallel/TaskPool.h"

#include <algorithm>
#include <atomic>
#include <cmath>

namespace masse
{
namespace
{
/// How many blocks ahead of the one it solves the backward solve asks for a block's values (prefetchBlockValues):
/// a block takes some 200 ns to solve at 128x2x128, a read from memory some 100 ns.
constexpr Eigen::Index prefetchBlocks = 2;

/// Asks the memory for block `block`'s values before the backward solve reaches it. The backward solve walks the
/// blocks from the last down, each block's values read upwards, so its reads jump back at every block: a factor that
/// no longer fits in the cache (128x2x128) would wait on memory for each block, and the backward solve would take
/// twice as long as the forward one, which reads the same values upwards throughout. A block's runs are laid out one
/// after another. Reads nothing into the arithmetic: the bits are the same.
[[gnu::always_inline]] inline void prefetchBlockValues(const MassBlockRows::View& rows, Eigen::Index block)
{
    const auto first = rows.blockRuns[block];
    const auto last = rows.blockRuns[block + 1];
    if (first == last)
    {
        return;
    }
    const auto* begin = reinterpret_cast<const char*>(rows.values + rows.runStart[first]);
    const auto* end =
        reinterpret_cast<const char*>(rows.values + rows.runStart[last - 1] + 3 * rows.runLength[last - 1]);
    for (const char* line = begin; line < end; line += 64)
    {
        __builtin_prefetch(line, 0, 3);
    }
}

// One copy of each triangular solve per SIMD path: only the instruction set differs (see SimdPath.h for why the bits
// do not).
#define MASSE_TRIANGULAR_KERNELS(suffix, targetAttribute, dots, scatter)                                               \
    /* L y = b in place on y over the masses [begin, end) (their rows 3m to 3m+2), from the first up: each row's y_i   \
       less its sum over L's row below the mass's block, then less the block's entries times the rows above it. */     \
    targetAttribute void forwardBlocks##suffix(const MassBlockRows::View& rows, float* y, Eigen::Index begin,          \
                                               Eigen::Index end)                                                       \
    {                                                                                                                  \
        for (Eigen::Index m = begin; m < end; ++m)                                                                     \
        {                                                                                                              \
            float s[3];                                                                                                \
            dots(rows, m, y, s);                                                                                       \
            const float* e = rows.inBlock + 3 * m;                                                                     \
            float* ym = y + 3 * m;                                                                                     \
            ym[0] -= s[0];                                                                                             \
            ym[1] = (ym[1] - s[1]) - e[0] * ym[0];                                                                     \
            ym[2] = ((ym[2] - s[2]) - e[1] * ym[0]) - e[2] * ym[1];                                                    \
        }                                                                                                              \
    }                                                                                                                  \
    /* D L^T x = y in place on x over the masses [begin, end), from the last down: x_j = y_j / d_j - w_j - the         \
       block's entries below j times their x, w_j = sum over the rows i below the block of L_ij x_i, which each block  \
       adds to w once its x is solved (every row i > j with an entry in column j is j's ancestor in the elimination    \
       tree, solved before j in this range or in a later stage). */                                                    \
    targetAttribute void backwardBlocks##suffix(const MassBlockRows::View& rows, const float* d, float* x, float* w,   \
                                                Eigen::Index begin, Eigen::Index end, Eigen::Index prefetchAhead)      \
    {                                                                                                                  \
        for (Eigen::Index m = end - 1; m >= begin; --m)                                                                \
        {                                                                                                              \
            if (prefetchAhead > 0 && m - prefetchAhead >= begin)                                                       \
            {                                                                                                          \
                prefetchBlockValues(rows, m - prefetchAhead);                                                          \
            }                                                                                                          \
            const float* e = rows.inBlock + 3 * m;                                                                     \
            float* xm = x + 3 * m;                                                                                     \
            const float* dm = d + 3 * m;                                                                               \
            const float* wm = w + 3 * m;                                                                               \
            xm[2] = xm[2] / dm[2] - wm[2];                                                                             \
            xm[1] = (xm[1] / dm[1] - wm[1]) - e[2] * xm[2];                                                            \
            xm[0] = ((xm[0] / dm[0] - wm[0]) - e[0] * xm[1]) - e[1] * xm[2];                                           \
            scatter(rows, m, xm, w);                                                                                   \
        }                                                                                                              \
    }

// The vector paths have kernels of their own (MassBlockRows.h: a run's last few entries under a mask, the halves read
// by F16C's instruction); the default path reads the halves from halfFloats. All exact.
[[gnu::always_inline]] inline void blockDotsDefault(const MassBlockRows::View& m, Eigen::Index block, const float* x,
                                                    float s[3])
{
    const float* floats = halfFloats();
    blockDots(
        m, block, x, [floats](std::uint16_t half) { return floats[half]; }, s);
}
[[gnu::always_inline]] inline void blockScatterDefault(const MassBlockRows::View& m, Eigen::Index block,
                                                       const float x[3], float* w)
{
    const float* floats = halfFloats();
    blockScatter(m, block, x, w, [floats](std::uint16_t half) { return floats[half]; });
}
MASSE_TRIANGULAR_KERNELS(Default, , blockDotsDefault, blockScatterDefault)
#if defined(__x86_64__) && defined(__GNUC__)
MASSE_TRIANGULAR_KERNELS(Avx2, __attribute__((target("avx2,f16c"))), blockDotsAvx2, blockScatterAvx2)
MASSE_TRIANGULAR_KERNELS(Avx512, __attribute__((target("avx512f"))), blockDotsAvx512, blockScatterAvx512)
#endif
#undef MASSE_TRIANGULAR_KERNELS

/// Masses a task of the diagonal's following and of the filter handles.
constexpr std::size_t followChunkSize = 2048;
/// Rows a task of the copies, permutations and scalings of the solve's vectors handles: a few pages of each vector.
constexpr std::size_t vectorChunkSize = 8192;

/// The lower Cholesky factor of a diagonal block, in plain arithmetic (the same bits wherever it runs); false if the
/// block is not positive definite.
bool blockCholesky(const Mat3& b, Mat3& c)
{
    c.setZero();
    for (int j = 0; j < 3; ++j)
    {
        Real pivot = b(j, j);
        for (int k = 0; k < j; ++k)
        {
            pivot -= c(j, k) * c(j, k);
        }
        if (!(pivot > 0))
        {
            return false;
        }
        c(j, j) = std::sqrt(pivot);
        for (int i = j + 1; i < 3; ++i)
        {
            Real sum = b(i, j);
            for (int k = 0; k < j; ++k)
            {
                sum -= c(i, k) * c(j, k);
            }
            c(i, j) = sum / c(j, j);
        }
    }
    return true;
}

void forwardBlocksOn(SimdPath path, const MassBlockRows::View& rows, float* y, Eigen::Index begin, Eigen::Index end)
{
    switch (path)
    {
#if defined(__x86_64__) && defined(__GNUC__)
    case SimdPath::Avx512:
        return forwardBlocksAvx512(rows, y, begin, end);
    case SimdPath::Avx2:
        return forwardBlocksAvx2(rows, y, begin, end);
#endif
    default:
        return forwardBlocksDefault(rows, y, begin, end);
    }
}

void backwardBlocksOn(SimdPath path, const MassBlockRows::View& rows, const float* d, float* x, float* w,
                      Eigen::Index begin, Eigen::Index end, Eigen::Index prefetchAhead)
{
    switch (path)
    {
#if defined(__x86_64__) && defined(__GNUC__)
    case SimdPath::Avx512:
        return backwardBlocksAvx512(rows, d, x, w, begin, end, prefetchAhead);
    case SimdPath::Avx2:
        return backwardBlocksAvx2(rows, d, x, w, begin, end, prefetchAhead);
#endif
    default:
        return backwardBlocksDefault(rows, d, x, w, begin, end, prefetchAhead);
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
    m_permutedSources = fullSymmetricPermutation(a, m_permutation.indices().data(), m_permutedMatrix);
    gatherPermutedValues(a, m_permutedSources, m_permutedMatrix);
    m_factor.analyse(m_permutedMatrix, m_stages);
    // Following needs each mass's whole 3x3 block in the pattern (the implicit matrix has it; a matrix whose
    // coordinates are uncoupled does not, and its factor is used as it is).
    const auto* outer = a.outerIndexPtr();
    const auto* inner = a.innerIndexPtr();
    m_diagonalSlots.resize(std::size_t(a.cols() / 3));
    m_canFollow = true;
    for (std::size_t mass = 0; mass < m_diagonalSlots.size(); ++mass)
    {
        for (int c = 0; c < 3; ++c)
        {
            const auto column = Eigen::Index(3 * mass) + c;
            const auto top = SparseMatrix::StorageIndex(3 * mass);
            const auto* end = inner + outer[column + 1];
            const auto* found = std::lower_bound(inner + outer[column], end, top);
            m_canFollow =
                m_canFollow && end - found >= 3 && found[0] == top && found[1] == top + 1 && found[2] == top + 2;
            m_diagonalSlots[mass][std::size_t(c)] = SparseMatrix::StorageIndex(found - inner);
        }
    }
    m_factoredBlocks.resize(m_diagonalSlots.size());
    m_following.resize(m_diagonalSlots.size());
    m_followed = false;
    m_ready = false;
    m_rowsLaidOut = false;
    m_filtered.resize(a.rows());
    m_permuted.resize(std::size_t(a.rows()));
    m_scattered.resize(std::size_t(a.rows()));
}

bool CholeskyPreconditioner::refresh(const SparseMatrix& a)
{
    // A refresh (not every step) copies the matrix into the factor's order; the pattern is unchanged.
    gatherPermutedValues(a, m_permutedSources, m_permutedMatrix);
    m_ready = m_factor.factorize(m_permutedMatrix);
    m_followed = false;
    m_blocksFactored = false;
    if (m_ready && m_canFollow)
    {
        // The blocks the factor follows from (positive definite, as the matrix is, unless rounding says otherwise;
        // then the factor is used as it is until the next refresh).
        std::atomic<bool> blocksPositive{true};
        parallelFor(m_factoredBlocks.size(), followChunkSize,
                    [&](std::size_t begin, std::size_t end)
                    {
                        for (std::size_t mass = begin; mass < end; ++mass)
                        {
                            if (!blockCholesky(SlotMatrix<3>::read(a, m_diagonalSlots[mass]), m_factoredBlocks[mass]))
                            {
                                blocksPositive = false;
                            }
                        }
                    });
        m_blocksFactored = blocksPositive;
    }
    if (m_ready)
    {
        // The solves' copy of the factor: its runs depend only on the factor's pattern, the analysed one at every
        // refresh, so they are laid out at the first refresh, and later ones write the values.
        const auto& lower = m_factor.lower();
        m_rowsLaidOut ? m_rows.refillLowerRows(lower) : m_rows.assignLowerRows(lower);
        m_rowsLaidOut = true;
    }
    ++m_refreshCount;
    return m_ready;
}

bool CholeskyPreconditioner::followDiagonal(const SparseMatrix& a)
{
    m_followed = false;
    if (!m_ready || !m_blocksFactored)
    {
        return false;
    }
    std::atomic<bool> blocksPositive{true};
    parallelFor(m_following.size(), followChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    for (std::size_t mass = begin; mass < end; ++mass)
                    {
                        Mat3 current;
                        if (!blockCholesky(SlotMatrix<3>::read(a, m_diagonalSlots[mass]), current))
                        {
                            blocksPositive = false;
                            continue;
                        }
                        const Mat3& factored = m_factoredBlocks[mass];
                        // C C'^-1, both lower triangular: the identity, exactly, where the block has not moved.
                        m_following[mass] = current == factored ? Mat3(Mat3::Identity())
                                                                : Mat3(current.transpose()
                                                                           .triangularView<Eigen::Upper>()
                                                                           .solve(factored.transpose())
                                                                           .transpose());
                    }
                });
    m_followed = blocksPositive;
    return m_followed;
}

void CholeskyPreconditioner::setFilter(const std::vector<Index>& masses, const std::vector<Mat3>& filters)
{
    m_masses = &masses;
    m_filters = &filters;
}

void CholeskyPreconditioner::apply(const Vector& r, Vector& z) const
{
    // Every pass below writes each row from its own inputs alone, so it runs on the pool with the bits of a loop.
    const bool filtered = m_masses && !m_masses->empty();
    const Vector* input = &r;
    if (filtered || m_followed)
    {
        m_filtered.resize(r.size());
        parallelFor(std::size_t(r.size()), vectorChunkSize,
                    [&](std::size_t begin, std::size_t end)
                    {
                        const auto count = Eigen::Index(end - begin);
                        m_filtered.segment(Eigen::Index(begin), count) = r.segment(Eigen::Index(begin), count);
                    });
        input = &m_filtered;
    }
    if (filtered)
    {
        parallelFor(m_masses->size(), followChunkSize,
                    [&](std::size_t begin, std::size_t end)
                    {
                        for (std::size_t k = begin; k < end; ++k)
                        {
                            const Eigen::Index row = Eigen::Index(3 * (*m_masses)[k]);
                            m_filtered.segment<3>(row) = (*m_filters)[k] * r.segment<3>(row);
                        }
                    });
    }
    if (m_followed) // R^-T on the way in
    {
        parallelFor(m_following.size(), followChunkSize,
                    [&](std::size_t begin, std::size_t end)
                    {
                        for (std::size_t mass = begin; mass < end; ++mass)
                        {
                            const auto row = Eigen::Index(3 * mass);
                            m_filtered.segment<3>(row) = m_following[mass] * m_filtered.segment<3>(row);
                        }
                    });
    }
    solveWithFactor(*input, z);
    if (m_followed) // R^-1 on the way out
    {
        parallelFor(m_following.size(), followChunkSize,
                    [&](std::size_t begin, std::size_t end)
                    {
                        for (std::size_t mass = begin; mass < end; ++mass)
                        {
                            const auto row = Eigen::Index(3 * mass);
                            z.segment<3>(row) = m_following[mass].transpose() * z.segment<3>(row);
                        }
                    });
    }
    if (filtered)
    {
        parallelFor(m_masses->size(), followChunkSize,
                    [&](std::size_t begin, std::size_t end)
                    {
                        for (std::size_t k = begin; k < end; ++k)
                        {
                            const Eigen::Index row = Eigen::Index(3 * (*m_masses)[k]);
                            const Mat3& s = (*m_filters)[k];
                            const Vec3 free = s * z.segment<3>(row);
                            z.segment<3>(row) = free + (r.segment<3>(row) - s * r.segment<3>(row));
                        }
                    });
    }
}

void CholeskyPreconditioner::solveWithFactor(const Vector& b, Vector& x) const
{
    // P^T L D L^T P x = b, spelled out rather than through SimplicialLDLT::solve, whose in-place permutation
    // allocates a mask on every call. Both triangular solves run the ranges of each stage (see DissectionOrder) on the
    // pool, the forward one from the first stage, the backward one from the last. The forward one computes every entry
    // by one gather in a fixed order whoever runs it (blockDots); in the backward one, the blocks that scatter into a
    // column are its ancestors in the elimination tree, which scatter in a fixed order (the later stages first, and
    // within a range from its last block down), so the bits do not depend on the thread count. They run in single
    // precision on the factor's half values (see MassBlockRows); r and z stay double. b is scaled by a power
    // of two to a largest entry in [1, 2) on the way in, and x back on the way out: a float's range is far narrower
    // than a double's, and a residual of 1e-40 or 1e40 would otherwise flush to zero or overflow. A power of two
    // scales every rounding with it, so where nothing would have left the float range the bits are those of no scaling.
    // The permutations, the scaling and the largest entry run on the pool: each row is written from its own entry,
    // and a largest does not depend on how the rows are split.
    const auto& permutation = m_permutation.indices();
    const std::size_t n = std::size_t(b.size());
    const std::size_t chunks = chunkCount(n, vectorChunkSize);
    m_chunkLargest.assign(chunks, 0);
    parallelFor(n, vectorChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    Real largest = 0;
                    for (std::size_t i = begin; i < end; ++i)
                    {
                        const Real magnitude = std::abs(b[Eigen::Index(i)]);
                        // A NaN is taken, and kept (nothing compares greater), to be seen below.
                        largest = magnitude > largest || std::isnan(magnitude) ? magnitude : largest;
                    }
                    m_chunkLargest[begin / vectorChunkSize] = largest;
                });
    Real largest = 0;
    for (const Real chunkLargest : m_chunkLargest)
    {
        largest = chunkLargest > largest || std::isnan(chunkLargest) ? chunkLargest : largest;
    }
    if (!(largest > 0) || !std::isfinite(largest))
    {
        x = b; // zero stays zero; a non-finite residual passes through to the run's finite check
        return;
    }
    const int exponent = std::ilogb(largest);
    const Real down = std::ldexp(Real(1), -exponent);
    const Real up = std::ldexp(Real(1), exponent); // multiplying by it rounds as ldexp would, without a call an entry
    parallelFor(n, vectorChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    for (std::size_t i = begin; i < end; ++i)
                    {
                        m_permuted[std::size_t(permutation[Eigen::Index(i)])] = float(b[Eigen::Index(i)] * down);
                        m_scattered[i] = 0.0f;
                    }
                });
    const SimdPath path = activeSimdPath();
    const MassBlockRows::View rows = m_rows.view();
    float* work = m_permuted.data();
    for (const std::vector<OrderRange>& ranges : m_stages)
    {
        runChunks(
            ranges.size(), [&](std::size_t k)
            { forwardBlocksOn(path, rows, work, Eigen::Index(ranges[k].begin / 3), Eigen::Index(ranges[k].end / 3)); });
    }
    // The backward solve asks for its blocks ahead where the factor streams from memory (prefetchBlockValues); a
    // factor that stays in the cache needs no prefetching, which would only cost its instructions.
    const Eigen::Index prefetchAhead = prefetchesFactor() ? prefetchBlocks : 0;
    for (auto stage = m_stages.rbegin(); stage != m_stages.rend(); ++stage)
    {
        const std::vector<OrderRange>& ranges = *stage;
        runChunks(ranges.size(),
                  [&](std::size_t k)
                  {
                      backwardBlocksOn(path, rows, m_factor.diagonal().data(), work, m_scattered.data(),
                                       Eigen::Index(ranges[k].begin / 3), Eigen::Index(ranges[k].end / 3),
                                       prefetchAhead);
                  });
    }
    parallelFor(n, vectorChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    for (std::size_t i = begin; i < end; ++i)
                    {
                        x[Eigen::Index(i)] = Real(m_permuted[std::size_t(permutation[Eigen::Index(i)])]) * up;
                    }
                });
}

} // namespace masse
