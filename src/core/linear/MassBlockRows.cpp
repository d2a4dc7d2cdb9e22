#include "core/linear/MassBlockRows.h"

#include "core/parallel/TaskPool.h"

#include <stdexcept>
#include <string>

namespace masse
{
namespace
{
using StorageIndex = MassBlockRows::StorageIndex;

/// Calls visit(row, column, value) for every entry of `lower`'s strictly lower part in columns [begin, end), walking
/// the columns in increasing order, which gives each row's entries in increasing column.
template <class Visit>
void forEachStrictlyLower(const Eigen::SparseMatrix<Real>& lower, Eigen::Index begin, Eigen::Index end,
                          const Visit& visit)
{
    const auto* outer = lower.outerIndexPtr();
    const auto* inner = lower.innerIndexPtr();
    const Real* values = lower.valuePtr();
    for (Eigen::Index column = begin; column < end; ++column)
    {
        for (auto k = outer[column]; k < outer[column + 1]; ++k)
        {
            if (inner[k] > column)
            {
                visit(inner[k], StorageIndex(column), values[k]);
            }
        }
    }
}

/// A row's entry in column `column` is in its mass's block from the mass's first column on (-1 below it): it
/// multiplies the result of the block's row `column - 3 * mass`.
int blockRowOf(StorageIndex row, StorageIndex column)
{
    const StorageIndex first = row - row % 3;
    return column >= first ? int(column - first) : -1;
}
} // namespace

void MassBlockRows::assignLowerRows(const SparseMatrix& lower)
{
    if (lower.rows() != lower.cols() || lower.cols() % 3 != 0)
    {
        throw std::invalid_argument("MassBlockRows: the factor must be square with three rows a mass, not " +
                                    std::to_string(lower.rows()) + "x" + std::to_string(lower.cols()));
    }
    const std::size_t blocks = std::size_t(lower.cols()) / 3;
    // Each block's shared columns are the union of its rows' (the same pattern three times over for the implicit
    // matrix's 3x3 blocks; where a row lacks a column of the others, its value stays zero). Walking the columns in
    // increasing order gives each block's in increasing order, once a row. A column starts a run unless the block's
    // previous one is at most joinGap columns before it.
    const auto forEachShared = [&](const auto& visit)
    {
        forEachStrictlyLower(lower, 0, lower.cols(),
                             [&](StorageIndex row, StorageIndex column, Real)
                             {
                                 if (blockRowOf(row, column) < 0)
                                 {
                                     visit(std::size_t(row) / 3, column);
                                 }
                             });
    };
    m_blockRuns.assign(blocks + 1, 0);
    std::vector<StorageIndex> lastColumn(blocks, -joinGap - 1); // per block, its last shared column so far
    forEachShared(
        [&](std::size_t block, StorageIndex column)
        {
            const StorageIndex last = lastColumn[block];
            if (column - last > joinGap)
            {
                ++m_blockRuns[block + 1];
            }
            lastColumn[block] = column;
        });
    for (std::size_t b = 0; b < blocks; ++b)
    {
        m_blockRuns[b + 1] += m_blockRuns[b];
    }
    const std::size_t runCount = std::size_t(m_blockRuns[blocks]);
    m_runColumn.resize(runCount);
    m_runLength.resize(runCount);
    m_runStart.resize(runCount + 1);
    // Lay the runs out: a block's runs in increasing column, the blocks in order.
    std::vector<StorageIndex> nextRun(m_blockRuns.begin(), m_blockRuns.end() - 1); // per block, its next run
    lastColumn.assign(blocks, -joinGap - 1);
    forEachShared(
        [&](std::size_t block, StorageIndex column)
        {
            const StorageIndex last = lastColumn[block];
            if (column == last)
            {
                return;
            }
            if (column - last > joinGap)
            {
                const std::size_t run = std::size_t(nextRun[block]++);
                m_runColumn[run] = column;
                m_runLength[run] = 1;
            }
            else
            {
                m_runLength[std::size_t(nextRun[block]) - 1] += column - last;
            }
            lastColumn[block] = column;
        });
    m_runStart[0] = 0;
    for (std::size_t r = 0; r < runCount; ++r)
    {
        m_runStart[r + 1] = m_runStart[r] + 3 * m_runLength[r];
    }
    m_values.assign(std::size_t(m_runStart[runCount]) + valuePadding, 0);
    m_inBlock.assign(3 * blocks, 0.0f);
    refillLowerRows(lower);
}

void MassBlockRows::refillLowerRows(const SparseMatrix& lower)
{
    // Every entry has a place of its own, found from its block's runs alone (a block has two or three on average), so
    // the columns are written in chunks on the pool: a refresh is on the implicit step's critical path.
    parallelFor(std::size_t(lower.cols()), refillColumnsPerChunk,
                [&](std::size_t begin, std::size_t end)
                {
                    forEachStrictlyLower(lower, Eigen::Index(begin), Eigen::Index(end),
                                         [&](StorageIndex row, StorageIndex column, Real value)
                                         { write(row, column, value); });
                });
}

void MassBlockRows::write(StorageIndex row, StorageIndex column, Real value)
{
    const std::size_t block = std::size_t(row) / 3;
    const int rowOfBlock = int(row % 3);
    const int blockRow = blockRowOf(row, column);
    if (blockRow >= 0)
    {
        // Row 1's one in-block entry multiplies row 0's result; row 2's two, rows 0 and 1's.
        m_inBlock[3 * block + std::size_t(rowOfBlock == 1 ? 0 : 1 + blockRow)] = floatFromHalf(halfFromReal(value));
        return;
    }
    // The runs of the pattern laid out hold every shared column of the block.
    auto run = std::size_t(m_blockRuns[block]);
    while (column - m_runColumn[run] >= m_runLength[run])
    {
        ++run;
    }
    m_values[std::size_t(m_runStart[run]) + runValueOffset(m_runLength[run], rowOfBlock, column - m_runColumn[run])] =
        halfFromReal(value);
}
} // namespace masse
