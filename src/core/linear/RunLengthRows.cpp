#include "core/linear/RunLengthRows.h"

namespace masse
{
template <class ForEachEntry> void RunLengthRows::assign(Eigen::Index rowCount, const ForEachEntry& forEachEntry)
{
    const std::size_t n = std::size_t(rowCount);
    // Count each row's entries and runs: an entry starts a run unless the row's previous entry is at most joinGap
    // columns before it (the columns between are stored as zeros).
    m_nextValue.assign(n + 1, 0);
    m_nextRun.assign(n + 1, 0);
    m_lastColumn.assign(n, -2);
    forEachEntry(
        [&](StorageIndex row, StorageIndex column, Real)
        {
            const StorageIndex last = m_lastColumn[std::size_t(row)];
            if (last >= 0 && column - last <= joinGap)
            {
                m_nextValue[std::size_t(row) + 1] += column - last;
            }
            else
            {
                ++m_nextValue[std::size_t(row) + 1];
                ++m_nextRun[std::size_t(row) + 1];
            }
            m_lastColumn[std::size_t(row)] = column;
        });
    for (std::size_t i = 0; i < n; ++i)
    {
        m_nextValue[i + 1] += m_nextValue[i];
        m_nextRun[i + 1] += m_nextRun[i];
    }
    m_rowRuns.assign(m_nextRun.begin(), m_nextRun.end());
    m_runColumn.resize(std::size_t(m_nextRun[n]));
    m_runStart.resize(std::size_t(m_nextRun[n]) + 1);
    m_runStart.back() = m_nextValue[n];
    m_values.assign(std::size_t(m_nextValue[n]) + valuePadding, 0);
    // Fill. Rows and their runs are laid out in order, so a run's values end where the next run's begin.
    m_lastColumn.assign(n, -2);
    forEachEntry(
        [&](StorageIndex row, StorageIndex column, Real value)
        {
            const std::size_t i = std::size_t(row);
            const StorageIndex last = m_lastColumn[i];
            if (last >= 0 && column - last <= joinGap)
            {
                m_nextValue[i] += column - last - 1; // the gap's entries stay zero
            }
            else
            {
                const std::size_t run = std::size_t(m_nextRun[i]++);
                m_runColumn[run] = column;
                m_runStart[run] = m_nextValue[i];
            }
            m_values[std::size_t(m_nextValue[i]++)] = halfFromReal(value);
            m_lastColumn[i] = column;
        });
}

template <class ForEachEntry> void RunLengthRows::refill(const ForEachEntry& forEachEntry)
{
    // Each row's entries come in increasing column, so its run only moves forward: the run holding a column is the
    // current one, or a later one once the column is past the current one's end.
    m_nextRun.assign(m_rowRuns.begin(), m_rowRuns.end());
    forEachEntry(
        [&](StorageIndex row, StorageIndex column, Real value)
        {
            StorageIndex& run = m_nextRun[std::size_t(row)];
            while (column - m_runColumn[std::size_t(run)] >=
                   m_runStart[std::size_t(run) + 1] - m_runStart[std::size_t(run)])
            {
                ++run;
            }
            m_values[std::size_t(m_runStart[std::size_t(run)] + column - m_runColumn[std::size_t(run)])] =
                halfFromReal(value);
        });
}

namespace
{
/// Calls visit(column, row, value) for every entry of `lower`'s strictly lower part, column by column in increasing
/// order, each column's rows increasing.
template <class Visit> void forEachStrictlyLower(const Eigen::SparseMatrix<Real>& lower, const Visit& visit)
{
    const auto* outer = lower.outerIndexPtr();
    const auto* inner = lower.innerIndexPtr();
    const Real* values = lower.valuePtr();
    for (Eigen::Index column = 0; column < lower.cols(); ++column)
    {
        for (auto k = outer[column]; k < outer[column + 1]; ++k)
        {
            if (inner[k] > column)
            {
                visit(RunLengthRows::StorageIndex(column), inner[k], values[k]);
            }
        }
    }
}

/// `lower`'s strictly lower entries as assign and refill take them, by rows: visit(row, column, value), walking the
/// columns in increasing order, which gives each row's entries in increasing column.
auto byRows(const Eigen::SparseMatrix<Real>& lower)
{
    return [&lower](const auto& visit)
    {
        forEachStrictlyLower(lower, [&](RunLengthRows::StorageIndex column, RunLengthRows::StorageIndex row, Real value)
                             { visit(row, column, value); });
    };
}

/// The same by columns, the last first: column j is row n-1-j, its entries in increasing row.
auto byColumnsLastFirst(const Eigen::SparseMatrix<Real>& lower)
{
    return [&lower](const auto& visit)
    {
        const auto last = RunLengthRows::StorageIndex(lower.cols() - 1);
        forEachStrictlyLower(lower, [&](RunLengthRows::StorageIndex column, RunLengthRows::StorageIndex row, Real value)
                             { visit(last - column, row, value); });
    };
}
} // namespace

void RunLengthRows::assignLowerRows(const SparseMatrix& lower)
{
    assign(lower.cols(), byRows(lower));
}

void RunLengthRows::assignLowerColumnsLastFirst(const SparseMatrix& lower)
{
    assign(lower.cols(), byColumnsLastFirst(lower));
}

void RunLengthRows::refillLowerRows(const SparseMatrix& lower)
{
    refill(byRows(lower));
}

void RunLengthRows::refillLowerColumnsLastFirst(const SparseMatrix& lower)
{
    refill(byColumnsLastFirst(lower));
}
} // namespace masse
