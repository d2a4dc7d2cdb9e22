#include "SpringRuns.h"

#include "SpringAdjacency.h"
#include "SpringSet.h"

#include <algorithm>
#include <numeric>

namespace masse
{
SpringRuns buildSpringRuns(const std::vector<SpringEnds>& ends, std::size_t massCount)
{
    const SpringAdjacency adjacency = buildSpringAdjacency(ends, massCount);
    struct Neighbour
    {
        std::int64_t offset;
        Index spring;
    };
    // Each mass's springs by increasing offset (ties, two springs between one pair, by spring index).
    std::vector<Neighbour> sorted(adjacency.entries.size());
    std::size_t rankCount = 0;
    for (std::size_t i = 0; i < massCount; ++i)
    {
        const std::size_t begin = adjacency.offsets[i];
        const std::size_t end = adjacency.offsets[i + 1];
        for (std::size_t k = begin; k < end; ++k)
        {
            const SpringAdjacency::Entry e = adjacency.entries[k];
            sorted[k] = {std::int64_t(e.other) - std::int64_t(i), e.spring};
        }
        std::sort(sorted.begin() + std::ptrdiff_t(begin), sorted.begin() + std::ptrdiff_t(end),
                  [](const Neighbour& l, const Neighbour& r) {
                      return l.offset != r.offset ? l.offset < r.offset : l.spring < r.spring;
                  });
        rankCount = std::max(rankCount, end - begin);
    }

    SpringRuns result;
    result.springCount = ends.size();
    result.massCount = massCount;
    for (std::size_t rank = 0; rank < rankCount; ++rank)
    {
        result.rankStart.push_back(result.runs.size());
        bool open = false;
        for (std::size_t i = 0; i < massCount; ++i)
        {
            const std::size_t begin = adjacency.offsets[i];
            if (begin + rank >= adjacency.offsets[i + 1])
            {
                open = false;
                continue;
            }
            const Neighbour n = sorted[begin + rank];
            SpringRun* last = open ? &result.runs.back() : nullptr;
            if (last && last->otherOffset == n.offset && std::size_t(last->firstSpring) + last->count == n.spring)
            {
                ++last->count; // masses are visited in order, so i == firstMass + count here
                continue;
            }
            result.runs.push_back({Index(i), 1, n.spring, n.offset});
            open = true;
        }
    }
    result.rankStart.push_back(result.runs.size());

    for (std::size_t spring = 0; spring < ends.size(); ++spring)
    {
        const std::int64_t offset = std::int64_t(ends[spring].b) - std::int64_t(ends[spring].a);
        if (!result.springRuns.empty())
        {
            SpringRun& last = result.springRuns.back();
            if (last.otherOffset == offset && std::size_t(last.firstMass) + last.count == ends[spring].a)
            {
                ++last.count;
                continue;
            }
        }
        result.springRuns.push_back({ends[spring].a, 1, Index(spring), offset});
    }
    return result;
}

std::vector<std::size_t> springOrderForRuns(const std::vector<SpringEnds>& ends)
{
    std::vector<std::size_t> order(ends.size());
    std::iota(order.begin(), order.end(), std::size_t(0));
    const auto offset = [&](std::size_t s) { return std::int64_t(ends[s].b) - std::int64_t(ends[s].a); };
    std::stable_sort(order.begin(), order.end(), [&](std::size_t l, std::size_t r) {
        return offset(l) != offset(r) ? offset(l) < offset(r) : ends[l].a < ends[r].a;
    });
    return order;
}
} // namespace masse
