#pragma once
/// A sparse matrix stored by rows as runs of consecutive columns: each run keeps its first column and its values, and
/// no entry has an index of its own.
///
/// Made for the triangular solves with a nested-dissection Cholesky factor, which stream the whole factor on every
/// preconditioner application. A separator's masses are consecutive in the order, so the factor's rows and columns
/// are long runs (at 128x2x128, 25.8 million entries in 172,000 runs by rows, 727,000 by columns). Stored as runs, a
/// solve reads no index per entry and reads x contiguously, in vectors.
///
/// The values are single precision: the factor only preconditions the conjugate gradient, which converges in double
/// precision whatever the preconditioner's rounding (both solves read the same rounded factor, so it stays symmetric
/// positive definite). Half the bytes to stream: one preconditioner application at 128x2x128 took 13 ms with double
/// values, 10 ms with single, at two threads.

#include "Types.h"

#include <Eigen/SparseCore>

#include <vector>

namespace masse
{
class RunLengthRows
{
public:
    using SparseMatrix = Eigen::SparseMatrix<Real>;
    using StorageIndex = SparseMatrix::StorageIndex;

    /// The strictly lower part of `lower` (column-major, each column's rows increasing) by rows: row i holds L_ij for
    /// j < i, in increasing j.
    void assignLowerRows(const SparseMatrix& lower);
    /// The strictly lower part of `lower` by columns, the last column first: row q holds column n-1-q's entries L_iq'
    /// (q' = n-1-q, i > q'), in increasing i.
    void assignLowerColumnsLastFirst(const SparseMatrix& lower);

    Eigen::Index rows() const { return Eigen::Index(m_rowRuns.size()) - 1; }
    std::size_t entries() const { return m_values.size(); }
    std::size_t runs() const { return m_runColumn.size(); }

    /// The arrays, for the kernels (rowDot below).
    struct View
    {
        const StorageIndex* rowRuns;
        const StorageIndex* runColumn;
        const StorageIndex* runStart;
        const float* values;
    };
    View view() const { return {m_rowRuns.data(), m_runColumn.data(), m_runStart.data(), m_values.data()}; }

private:
    /// Fills the storage from `forEachEntry(visit)`, which calls visit(row, column, value) for every entry, each row's
    /// entries in increasing column (rows may interleave); called twice, to count and to fill.
    template <class ForEachEntry> void assign(Eigen::Index rowCount, const ForEachEntry& forEachEntry);

    std::vector<StorageIndex> m_rowRuns;   ///< runs of row i: [m_rowRuns[i], m_rowRuns[i + 1])
    std::vector<StorageIndex> m_runColumn; ///< first column of run r
    std::vector<StorageIndex> m_runStart;  ///< values of run r: [m_runStart[r], m_runStart[r + 1]); one past the last
    std::vector<float> m_values;
    std::vector<StorageIndex> m_nextValue; ///< scratch of assign(), kept so that a refresh does not allocate it anew
    std::vector<StorageIndex> m_nextRun;
    std::vector<StorageIndex> m_lastColumn;
};

/// sum over row i's entries of value * x[column], in a fixed order whoever calls it and on any vector width: `lanes`
/// running sums (4 or 8), entry t of a run going to sum t mod lanes, added pairwise at the end. Short runs want few
/// lanes (the entries past the last full group of lanes are added one by one). Inlined into each SIMD path's copy of
/// the caller (see SimdPath.h): only the instruction set differs.
template <int lanes>
[[gnu::always_inline]] inline Real rowDot(const RunLengthRows::View& m, Eigen::Index row, const Real* x)
{
    static_assert(lanes == 4 || lanes == 8);
    Real sum[lanes] = {};
    for (auto run = m.rowRuns[row]; run < m.rowRuns[row + 1]; ++run)
    {
        const float* v = m.values + m.runStart[run];
        const Real* xs = x + m.runColumn[run];
        const RunLengthRows::StorageIndex length = m.runStart[run + 1] - m.runStart[run];
        RunLengthRows::StorageIndex t = 0;
        for (; t + lanes <= length; t += lanes)
        {
            for (int lane = 0; lane < lanes; ++lane)
            {
                sum[lane] += Real(v[t + lane]) * xs[t + lane];
            }
        }
        for (int lane = 0; t + lane < length; ++lane)
        {
            sum[lane] += Real(v[t + lane]) * xs[t + lane];
        }
    }
    if constexpr (lanes == 4)
    {
        return (sum[0] + sum[1]) + (sum[2] + sum[3]);
    }
    else
    {
        return ((sum[0] + sum[1]) + (sum[2] + sum[3])) + ((sum[4] + sum[5]) + (sum[6] + sum[7]));
    }
}
} // namespace masse
