#include "CholeskyPreconditioner.h"

#include "TaskPool.h"

#include <algorithm>

namespace masse
{
namespace
{
/// sum over k of values[k] x[index[k]], in four running sums (k mod 4) added as (s0 + s1) + (s2 + s3): a fixed order,
/// the same at any thread count and vector width. One running sum, as a plain loop has, made each product wait for
/// the addition before it: the solves took four additions' latency per entry of the factor, most of the implicit
/// step at 128x2x128.
Real rowSum(const Real* values, const SparseMatrix::StorageIndex* index, std::size_t count, const Real* x)
{
    Real s0 = 0;
    Real s1 = 0;
    Real s2 = 0;
    Real s3 = 0;
    std::size_t k = 0;
    for (; k + 4 <= count; k += 4)
    {
        s0 += values[k] * x[index[k]];
        s1 += values[k + 1] * x[index[k + 1]];
        s2 += values[k + 2] * x[index[k + 2]];
        s3 += values[k + 3] * x[index[k + 3]];
    }
    for (; k < count; ++k)
    {
        s0 += values[k] * x[index[k]];
    }
    return (s0 + s1) + (s2 + s3);
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
    m_permutedMatrix = a.selfadjointView<Eigen::Lower>().twistedBy(m_permutation);
    m_factor.analyzePattern(m_permutedMatrix);
    m_ready = false;
    m_filtered.resize(a.rows());
    m_permuted.resize(a.rows());
}

bool CholeskyPreconditioner::refresh(const SparseMatrix& a)
{
    // A refresh (not every step) copies the matrix into the factor's order; the pattern is unchanged.
    m_permutedMatrix = a.selfadjointView<Eigen::Lower>().twistedBy(m_permutation);
    m_factor.factorize(m_permutedMatrix);
    m_ready = m_factor.info() == Eigen::Success;
    if (m_ready)
    {
        copyColumnsForBackwardSolve();
        copyRowsForForwardSolve();
        m_diagonal = m_factor.vectorD(); // vectorD() returns a copy: taken once here, not on every apply
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

void CholeskyPreconditioner::copyColumnsForBackwardSolve()
{
    const SparseMatrix& lower = m_factor.matrixL().nestedExpression();
    const auto* outer = lower.outerIndexPtr();
    const auto* inner = lower.innerIndexPtr();
    const Real* values = lower.valuePtr();
    const Eigen::Index n = lower.cols();
    m_backwardStart.resize(std::size_t(n) + 1);
    m_backwardRows.resize(std::size_t(outer[n]));
    m_backwardValues.resize(std::size_t(outer[n]));
    SparseMatrix::StorageIndex next = 0;
    for (Eigen::Index q = 0; q < n; ++q)
    {
        m_backwardStart[std::size_t(q)] = next;
        const Eigen::Index column = n - 1 - q;
        std::copy(inner + outer[column], inner + outer[column + 1], m_backwardRows.begin() + next);
        std::copy(values + outer[column], values + outer[column + 1], m_backwardValues.begin() + next);
        next += outer[column + 1] - outer[column];
    }
    m_backwardStart[std::size_t(n)] = next;
}

void CholeskyPreconditioner::copyRowsForForwardSolve()
{
    const SparseMatrix& lower = m_factor.matrixL().nestedExpression();
    const auto* outer = lower.outerIndexPtr();
    const auto* inner = lower.innerIndexPtr();
    const Real* values = lower.valuePtr();
    const Eigen::Index n = lower.cols();
    // A counting sort by row; walking the columns in increasing order leaves each row's entries in increasing column.
    m_forwardStart.assign(std::size_t(n) + 1, 0);
    for (Eigen::Index column = 0; column < n; ++column)
    {
        for (auto k = outer[column]; k < outer[column + 1]; ++k)
        {
            if (inner[k] > column)
            {
                ++m_forwardStart[std::size_t(inner[k]) + 1];
            }
        }
    }
    for (std::size_t row = 0; row < std::size_t(n); ++row)
    {
        m_forwardStart[row + 1] += m_forwardStart[row];
    }
    m_forwardColumns.resize(std::size_t(m_forwardStart[std::size_t(n)]));
    m_forwardValues.resize(m_forwardColumns.size());
    std::vector<SparseMatrix::StorageIndex> next(m_forwardStart.begin(), m_forwardStart.end() - 1);
    for (Eigen::Index column = 0; column < n; ++column)
    {
        for (auto k = outer[column]; k < outer[column + 1]; ++k)
        {
            if (inner[k] > column)
            {
                const auto slot = std::size_t(next[std::size_t(inner[k])]++);
                m_forwardColumns[slot] = SparseMatrix::StorageIndex(column);
                m_forwardValues[slot] = values[k];
            }
        }
    }
}

void CholeskyPreconditioner::forwardRows(Eigen::Index begin, Eigen::Index end) const
{
    // y_i = b_i - sum over L's row i of L_ij y_j (columns j < i).
    const auto* start = m_forwardStart.data();
    const auto* columns = m_forwardColumns.data();
    const Real* values = m_forwardValues.data();
    Real* y = m_permuted.data();
    for (Eigen::Index i = begin; i < end; ++i)
    {
        y[i] -= rowSum(values + start[i], columns + start[i], std::size_t(start[i + 1] - start[i]), y);
    }
}

void CholeskyPreconditioner::solveWithFactor(const Vector& b, Vector& x) const
{
    // P^T L D L^T P x = b, spelled out rather than through SimplicialLDLT::solve, whose in-place permutation
    // allocates a mask on every call. Both triangular solves run the ranges of each stage (see DissectionOrder) on the
    // pool, the forward one from the first stage, the backward one from the last, every entry computed by one gather
    // in a fixed order whoever runs it (rowSum), so the bits do not depend on the thread count.
    const auto& permutation = m_permutation.indices();
    const Eigen::Index n = b.size();
    for (Eigen::Index i = 0; i < n; ++i)
    {
        m_permuted[permutation[i]] = b[i];
    }
    for (const std::vector<OrderRange>& ranges : m_stages)
    {
        sharedPool().run(ranges.size(), [&](std::size_t k)
                         { forwardRows(Eigen::Index(ranges[k].begin), Eigen::Index(ranges[k].end)); });
    }
    for (auto stage = m_stages.rbegin(); stage != m_stages.rend(); ++stage)
    {
        const std::vector<OrderRange>& ranges = *stage;
        sharedPool().run(ranges.size(), [&](std::size_t k)
                         { backwardRows(Eigen::Index(ranges[k].begin), Eigen::Index(ranges[k].end)); });
    }
    for (Eigen::Index i = 0; i < n; ++i)
    {
        x[i] = m_permuted[permutation[i]];
    }
}

void CholeskyPreconditioner::backwardRows(Eigen::Index begin, Eigen::Index end) const
{
    // x_j = y_j / d_j - sum over L's column j of L_ij x_i (rows i > j).
    const Eigen::Index n = m_permuted.size();
    const auto* start = m_backwardStart.data();
    const auto* rows = m_backwardRows.data();
    const Real* values = m_backwardValues.data();
    const Real* d = m_diagonal.data();
    Real* x = m_permuted.data();
    for (Eigen::Index q = n - end; q < n - begin; ++q)
    {
        const Eigen::Index column = n - 1 - q;
        x[column] =
            x[column] / d[column] - rowSum(values + start[q], rows + start[q], std::size_t(start[q + 1] - start[q]), x);
    }
}
} // namespace masse
