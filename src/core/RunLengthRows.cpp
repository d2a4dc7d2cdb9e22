#include "RunLengthRows.h"

namespace masse
{
template <class ForEachEntry> void RunLengthRows::assign(Eigen::Index rowCount, const ForEachEntry& forEachEntry)
{
    const std::size_t n = std::size_t(rowCount);
    // Count each row's entries and runs: an entry starts a run unless the row's previous entry is the column before.
    m_nextValue.assign(n + 1, 0);
    m_nextRun.assign(n + 1, 0);
    m_lastColumn.assign(n, -2);
    forEachEntry(
        [&](StorageIndex row, StorageIndex column, Real)
        {
            ++m_nextValue[std::size_t(row) + 1];
            if (m_lastColumn[std::size_t(row)] != column - 1)
            {
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
    m_values.resize(std::size_t(m_nextValue[n]));
    // Fill. Rows and their runs are laid out in order, so a run's values end where the next run's begin.
    m_lastColumn.assign(n, -2);
    forEachEntry(
        [&](StorageIndex row, StorageIndex column, Real value)
        {
            const std::size_t i = std::size_t(row);
            if (m_lastColumn[i] != column - 1)
            {
                const std::size_t run = std::size_t(m_nextRun[i]++);
                m_runColumn[run] = column;
                m_runStart[run] = m_nextValue[i];
            }
            m_values[std::size_t(m_nextValue[i]++)] = float(value);
            m_lastColumn[i] = column;
        });
}

void RunLengthRows::assignLowerRows(const SparseMatrix& lower)
{
    const auto* outer = lower.outerIndexPtr();
    const auto* inner = lower.innerIndexPtr();
    const Real* values = lower.valuePtr();
    const Eigen::Index n = lower.cols();
    // Walking the columns in increasing order gives each row's entries in increasing column.
    assign(n,
           [&](const auto& visit)
           {
               for (Eigen::Index column = 0; column < n; ++column)
               {
                   for (auto k = outer[column]; k < outer[column + 1]; ++k)
                   {
                       if (inner[k] > column)
                       {
                           visit(inner[k], StorageIndex(column), values[k]);
                       }
                   }
               }
           });
}

void RunLengthRows::assignLowerColumnsLastFirst(const SparseMatrix& lower)
{
    const auto* outer = lower.outerIndexPtr();
    const auto* inner = lower.innerIndexPtr();
    const Real* values = lower.valuePtr();
    const Eigen::Index n = lower.cols();
    assign(n,
           [&](const auto& visit)
           {
               for (Eigen::Index column = 0; column < n; ++column)
               {
                   const auto row = StorageIndex(n - 1 - column);
                   for (auto k = outer[column]; k < outer[column + 1]; ++k)
                   {
                       if (inner[k] > column)
                       {
                           visit(row, inner[k], values[k]);
                       }
                   }
               }
           });
}

} // namespace masse
