#include "core/forces/SpringRowPlan.h"

#include "core/lattice/SpringTopology.h"

#include <algorithm>
#include <cstdlib>

namespace masse
{
namespace
{
/// Masses a band should hold: between about 4,000 and 8,000, whose state (72 bytes a mass) and spring forces stay in a
/// core's L2 cache. The rows before each band are computed twice (once for the band above, from the state in memory),
/// so larger bands cost less where a sheet has bands to spare: 8,192 at 256x2x256 (16 rows of 512 masses). A sheet
/// keeps about 8 bands for the threads down to 4,096 masses a band, and one smaller than that is one band, which the
/// kernel runs inline without waking a thread.
constexpr std::size_t smallestBand = 4096;
constexpr std::size_t largestBand = 8192;
constexpr std::size_t bandsWanted = 8;
} // namespace

std::shared_ptr<const SpringRowPlan> buildSpringRowPlan(const std::vector<SpringEnds>& ends,
                                                        const std::vector<SpringClass>& springClass,
                                                        const SpringAdjacency& adjacency,
                                                        const std::vector<int>& massRow)
{
    const std::size_t massCount = massRow.size();
    if (massCount == 0 || adjacency.massCount() != massCount || adjacency.springCount != ends.size() ||
        springClass.size() != ends.size())
    {
        return nullptr;
    }
    auto plan = std::make_shared<SpringRowPlan>();
    plan->massCount = massCount;
    plan->springCount = ends.size();
    plan->rowCount = std::size_t(*std::max_element(massRow.begin(), massRow.end())) + 1;
    if (*std::min_element(massRow.begin(), massRow.end()) < 0)
    {
        return nullptr;
    }
    const std::size_t rows = plan->rowCount;

    // Each spring's row and its slot in that row (springs keep increasing index within a row).
    std::vector<Index> springRow(ends.size());
    std::vector<Index> slot(ends.size());
    plan->slotCount.assign(rows, 0);
    std::vector<std::vector<Index>> springsOfRow(rows);
    for (std::size_t s = 0; s < ends.size(); ++s)
    {
        const int rowA = massRow[ends[s].a];
        const int rowB = massRow[ends[s].b];
        if (std::abs(rowA - rowB) > 1)
        {
            return nullptr;
        }
        springRow[s] = Index(std::min(rowA, rowB));
        slot[s] = plan->slotCount[springRow[s]]++;
        springsOfRow[springRow[s]].push_back(Index(s));
    }
    plan->largestSlotCount = *std::max_element(plan->slotCount.begin(), plan->slotCount.end());
    plan->springRunStart.push_back(0);
    for (std::size_t r = 0; r < rows; ++r)
    {
        for (const Index s : springsOfRow[r])
        {
            if (!plan->springRuns.empty() && plan->springRunStart.back() < plan->springRuns.size())
            {
                SpringRowPlan::SpringRun& run = plan->springRuns.back();
                if (s == run.firstSpring + run.count && ends[s].a == run.a + run.count &&
                    ends[s].b == run.b + run.count && std::uint8_t(springClass[s]) == run.springClass)
                {
                    ++run.count;
                    continue;
                }
            }
            SpringRowPlan::SpringRun run{s, ends[s].a, ends[s].b, 1, slot[s]};
            run.springClass = std::uint8_t(springClass[s]);
            plan->springRuns.push_back(run);
        }
        plan->springRunStart.push_back(Index(plan->springRuns.size()));
    }

    // Mass runs: a mass joins the previous mass's run when it is the next index, in the same row, and its entries
    // follow the run's pattern one slot on.
    std::vector<std::vector<Index>> massesOfRow(rows);
    for (std::size_t i = 0; i < massCount; ++i)
    {
        massesOfRow[std::size_t(massRow[i])].push_back(Index(i));
    }
    std::vector<SpringRowPlan::Entry> pattern;
    plan->massRunStart.push_back(0);
    for (std::size_t r = 0; r < rows; ++r)
    {
        for (const Index i : massesOfRow[r])
        {
            pattern.clear();
            for (std::size_t k = adjacency.offsets[i]; k < adjacency.offsets[i + 1]; ++k)
            {
                const Index s = adjacency.entries[k].spring;
                pattern.push_back({slot[s], std::uint8_t(springRow[s] == r ? 1 : 0), std::uint8_t(ends[s].b == i)});
            }
            if (!plan->massRuns.empty() && plan->massRunStart.back() < plan->massRuns.size())
            {
                SpringRowPlan::MassRun& run = plan->massRuns.back();
                bool follows = i == run.firstMass + run.count && pattern.size() == run.entryCount;
                for (std::size_t k = 0; follows && k < pattern.size(); ++k)
                {
                    const SpringRowPlan::Entry& e = plan->entries[run.firstEntry + k];
                    follows = pattern[k].slot == e.slot + run.count && pattern[k].sameRow == e.sameRow &&
                              pattern[k].negated == e.negated;
                }
                if (follows)
                {
                    ++run.count;
                    continue;
                }
            }
            plan->massRuns.push_back({i, 1, Index(plan->entries.size()), Index(pattern.size())});
            plan->entries.insert(plan->entries.end(), pattern.begin(), pattern.end());
        }
        plan->massRunStart.push_back(Index(plan->massRuns.size()));
    }
    const std::size_t massesPerRow = (massCount + rows - 1) / rows;
    const std::size_t massesPerBand = std::clamp(massCount / bandsWanted, smallestBand, largestBand);
    plan->bandRows = std::clamp<std::size_t>((massesPerBand + massesPerRow - 1) / massesPerRow, 1, rows);

    // Each band's masses as ranges of consecutive indices, and every mass's place in its band's copy.
    std::vector<Index> local(massCount);
    std::vector<Index> bandMasses;
    plan->bandRangeStart.push_back(0);
    for (std::size_t band = 0; band < plan->bandCount(); ++band)
    {
        const std::size_t begin = band * plan->bandRows;
        const std::size_t end = std::min(rows, begin + plan->bandRows);
        bandMasses.clear();
        for (std::size_t r = begin; r < end; ++r)
        {
            bandMasses.insert(bandMasses.end(), massesOfRow[r].begin(), massesOfRow[r].end());
        }
        std::sort(bandMasses.begin(), bandMasses.end());
        for (std::size_t k = 0; k < bandMasses.size(); ++k)
        {
            const Index i = bandMasses[k];
            local[i] = Index(k);
            if (k > 0 && i == bandMasses[k - 1] + 1)
            {
                ++plan->bandRanges.back().count;
            }
            else
            {
                plan->bandRanges.push_back({i, 1, Index(k)});
            }
        }
        plan->bandRangeStart.push_back(Index(plan->bandRanges.size()));
        plan->largestBandMassCount = std::max(plan->largestBandMassCount, bandMasses.size());
        // The springs of every row but the band's last (unless it is the sheet's last) join masses of the band, in
        // runs of consecutive places.
        const std::size_t ownSpringRowsEnd = end == rows ? end : end - 1;
        for (std::size_t r = begin; r < ownSpringRowsEnd; ++r)
        {
            for (Index k = plan->springRunStart[r]; k < plan->springRunStart[r + 1]; ++k)
            {
                SpringRowPlan::SpringRun& run = plan->springRuns[k];
                run.aLocal = local[run.a];
                run.bLocal = local[run.b];
            }
        }
        for (std::size_t r = begin; r < end; ++r)
        {
            for (Index k = plan->massRunStart[r]; k < plan->massRunStart[r + 1]; ++k)
            {
                plan->massRuns[k].local = local[plan->massRuns[k].firstMass];
            }
        }
    }
    return plan;
}
} // namespace masse
