#include "core/linear/MassBlockRows.h"

#include "core/forces/SimdPath.h"
#include "core/parallel/TaskPool.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace masse
{
namespace
{
using StorageIndex = MassBlockRows::StorageIndex;

/// Calls visit(row, column, k) for every entry of `lower`'s strictly lower part in columns [begin, end), k its index in
/// the value array, walking the columns in increasing order, which gives each row's entries in increasing column.
template <class Visit>
void forEachStrictlyLower(const Eigen::SparseMatrix<float>& lower, Eigen::Index begin, Eigen::Index end,
                          const Visit& visit)
{
    const auto* outer = lower.outerIndexPtr();
    const auto* inner = lower.innerIndexPtr();
    for (Eigen::Index column = begin; column < end; ++column)
    {
        for (auto k = outer[column]; k < outer[column + 1]; ++k)
        {
            if (inner[k] > column)
            {
                visit(inner[k], StorageIndex(column), std::size_t(k));
            }
        }
    }
}

/// Whether the `count` halves from `values` are all zero (+0 or -0).
bool allZero(const std::uint16_t* values, std::size_t count)
{
    unsigned bits = 0;
    for (std::size_t k = 0; k < count; ++k)
    {
        bits |= values[k];
    }
    return (bits & 0x7FFFu) == 0;
}

/// Calls keep(first, length) for each stretch [first, first + length) of a run's entries that the solves read (see
/// MassBlockRows::view): the longest stretches of its groups of sixteen entries, and of its last length mod 16, whose
/// values are not all zero, in increasing order. `values` are the run's, laid out as runValueOffset says.
template <class Keep> void forEachLiveStretch(const std::uint16_t* values, StorageIndex length, const Keep& keep)
{
    constexpr StorageIndex group = 16;
    const StorageIndex full = length / group * group;
    StorageIndex first = -1; // the stretch being gathered, -1 for none
    for (StorageIndex t = 0; t < full; t += group)
    {
        const bool zero = allZero(values + 3 * t, 3 * group);
        if (!zero && first < 0)
        {
            first = t;
        }
        else if (zero && first >= 0)
        {
            keep(first, t - first);
            first = -1;
        }
    }
    if (full < length && !allZero(values + 3 * full, std::size_t(3 * (length - full))))
    {
        keep(first >= 0 ? first : full, length - (first >= 0 ? first : full));
    }
    else if (first >= 0)
    {
        keep(first, full - first);
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
                             [&](StorageIndex row, StorageIndex column, std::size_t k)
                             {
                                 if (blockRowOf(row, column) < 0)
                                 {
                                     visit(std::size_t(row) / 3, column, k);
                                 }
                             });
    };
    m_blockRuns.assign(blocks + 1, 0);
    std::vector<StorageIndex> lastColumn(blocks, -joinGap - 1); // per block, its last shared column so far
    forEachShared(
        [&](std::size_t block, StorageIndex column, std::size_t)
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
    // Lay the runs out: a block's runs in increasing column, the blocks in order. Each shared entry's run is noted in
    // its place until the runs' lengths, which lay their values out, are known.
    m_place.assign(std::size_t(lower.outerIndexPtr()[lower.cols()]), noPlace);
    std::vector<StorageIndex> nextRun(m_blockRuns.begin(), m_blockRuns.end() - 1); // per block, its next run
    lastColumn.assign(blocks, -joinGap - 1);
    forEachShared(
        [&](std::size_t block, StorageIndex column, std::size_t k)
        {
            const StorageIndex last = lastColumn[block];
            if (column != last)
            {
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
            }
            m_place[k] = std::uint32_t(nextRun[block] - 1);
        });
    m_runStart[0] = 0;
    for (std::size_t r = 0; r < runCount; ++r)
    {
        m_runStart[r + 1] = m_runStart[r] + 3 * m_runLength[r];
    }
    m_values.assign(std::size_t(m_runStart[runCount]) + valuePadding, 0);
    m_inBlock.assign(3 * blocks, 0.0f);
    if (m_values.size() >= inBlockPlaces || 3 * blocks >= noPlace - inBlockPlaces)
    {
        throw std::invalid_argument("MassBlockRows: a factor of " + std::to_string(m_values.size()) +
                                    " stored values is too large for its places' 31 bits");
    }
    // Each entry's place is its own, from its run (or its block): columns in chunks on the pool.
    parallelFor(std::size_t(lower.cols()), placeColumnsPerChunk,
                [&](std::size_t begin, std::size_t end)
                {
                    forEachStrictlyLower(lower, Eigen::Index(begin), Eigen::Index(end),
                                         [&](StorageIndex row, StorageIndex column, std::size_t k)
                                         { m_place[k] = placeOf(row, column, m_place[k]); });
                });
    refillLowerRows(lower);
}

void MassBlockRows::refillLowerRows(const SparseMatrix& lower)
{
    // Every stored entry's place is found when the pattern is laid out (m_place), so a refill, on the implicit step's
    // critical path at every refresh, is one pass over the values in their storage order, in chunks on the pool,
    // with no search of the blocks' runs.
    if (std::size_t(lower.outerIndexPtr()[lower.cols()]) != m_place.size())
    {
        throw std::invalid_argument("MassBlockRows: a refill needs the pattern last assigned");
    }
    const float* values = lower.valuePtr();
    const bool f16c = activeSimdPath() != SimdPath::Default; // the AVX2 and AVX-512 paths have F16C (SimdPath.cpp)
    parallelFor(m_place.size(), refillEntriesPerChunk,
                [&](std::size_t begin, std::size_t end)
                {
                    std::size_t k = begin;
#if defined(__x86_64__) && defined(__GNUC__)
                    if (f16c)
                    {
                        k = refillF16c(values, begin, end);
                    }
#endif
                    for (; k < end; ++k)
                    {
                        store(k, halfFromReal(values[k]));
                    }
                });
    gatherLiveRuns();
}

void MassBlockRows::store(std::size_t k, std::uint16_t half)
{
    const std::uint32_t where = m_place[k];
    if (where < inBlockPlaces)
    {
        m_values[where] = half;
    }
    else if (where != noPlace)
    {
        m_inBlock[where - inBlockPlaces] = floatFromHalf(half);
    }
}

#if defined(__x86_64__) && defined(__GNUC__)
__attribute__((target("avx2,f16c"))) std::size_t MassBlockRows::refillF16c(const float* values, std::size_t begin,
                                                                           std::size_t end)
{
    std::size_t k = begin;
    for (; k + 8 <= end; k += 8)
    {
        alignas(16) std::uint16_t halves[8];
        _mm_store_si128(reinterpret_cast<__m128i*>(halves), halvesFromFloatsF16c(_mm256_loadu_ps(values + k)));
        for (std::size_t lane = 0; lane < 8; ++lane)
        {
            const float value = values[k + lane];
            store(k + lane, value == value ? halves[lane] : halfFromReal(value));
        }
    }
    return k;
}
#endif

void MassBlockRows::gatherLiveRuns()
{
    // Two passes over the blocks in chunks on the pool: each block's live runs and values counted, then, at the
    // places their running sums give, written.
    const std::size_t blockCount = m_blockRuns.size() - 1;
    m_live.blockRuns.assign(blockCount + 1, 0);
    m_live.blockValues.assign(blockCount + 1, 0);
    parallelFor(blockCount, gatherBlocksPerChunk,
                [&](std::size_t begin, std::size_t end)
                {
                    for (std::size_t b = begin; b < end; ++b)
                    {
                        StorageIndex runs = 0;
                        StorageIndex values = 0;
                        for (auto r = std::size_t(m_blockRuns[b]); r < std::size_t(m_blockRuns[b + 1]); ++r)
                        {
                            forEachLiveStretch(m_values.data() + m_runStart[r], m_runLength[r],
                                               [&](StorageIndex, StorageIndex length)
                                               {
                                                   ++runs;
                                                   values += 3 * length;
                                               });
                        }
                        m_live.blockRuns[b + 1] = runs;
                        m_live.blockValues[b + 1] = values;
                    }
                });
    for (std::size_t b = 0; b < blockCount; ++b)
    {
        m_live.blockRuns[b + 1] += m_live.blockRuns[b];
        m_live.blockValues[b + 1] += m_live.blockValues[b];
    }
    const auto runCount = std::size_t(m_live.blockRuns[blockCount]);
    m_live.runColumn.resize(runCount);
    m_live.runStart.resize(runCount);
    m_live.runLength.resize(runCount);
    // Every value before the padding is written below: only the padding needs its zeros.
    const auto liveValues = std::size_t(m_live.blockValues[blockCount]);
    m_live.values.resize(liveValues + valuePadding);
    std::fill(m_live.values.begin() + std::ptrdiff_t(liveValues), m_live.values.end(), std::uint16_t(0));
    parallelFor(blockCount, gatherBlocksPerChunk,
                [&](std::size_t begin, std::size_t end)
                {
                    for (std::size_t b = begin; b < end; ++b)
                    {
                        auto run = std::size_t(m_live.blockRuns[b]);
                        StorageIndex start = m_live.blockValues[b];
                        for (auto r = std::size_t(m_blockRuns[b]); r < std::size_t(m_blockRuns[b + 1]); ++r)
                        {
                            const std::uint16_t* values = m_values.data() + m_runStart[r];
                            forEachLiveStretch(values, m_runLength[r],
                                               [&](StorageIndex first, StorageIndex length)
                                               {
                                                   m_live.runColumn[run] = m_runColumn[r] + first;
                                                   m_live.runStart[run] = start;
                                                   m_live.runLength[run] = length;
                                                   std::copy(values + 3 * first, values + 3 * (first + length),
                                                             m_live.values.begin() + start);
                                                   ++run;
                                                   start += 3 * length;
                                               });
                        }
                    }
                });
}

std::uint32_t MassBlockRows::placeOf(StorageIndex row, StorageIndex column, std::uint32_t run) const
{
    const std::size_t block = std::size_t(row) / 3;
    const int rowOfBlock = int(row % 3);
    const int blockRow = blockRowOf(row, column);
    if (blockRow >= 0)
    {
        // Row 1's one in-block entry multiplies row 0's result; row 2's two, rows 0 and 1's.
        return inBlockPlaces + std::uint32_t(3 * block + std::size_t(rowOfBlock == 1 ? 0 : 1 + blockRow));
    }
    return std::uint32_t(std::size_t(m_runStart[run]) +
                         runValueOffset(m_runLength[run], rowOfBlock, column - m_runColumn[run]));
}
} // namespace masse
