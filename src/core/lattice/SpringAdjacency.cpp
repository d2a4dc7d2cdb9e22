#include "core/lattice/SpringAdjacency.h"

#include "core/lattice/SpringTopology.h"

#include <stdexcept>
#include <string>

namespace masse
{
SpringAdjacency buildSpringAdjacency(const std::vector<SpringEnds>& ends, std::size_t massCount)
{
    SpringAdjacency adjacency;
    adjacency.springCount = ends.size();
    adjacency.offsets.assign(massCount + 1, 0);
    for (const SpringEnds& e : ends)
    {
        if (e.a >= massCount || e.b >= massCount)
        {
            throw std::out_of_range("a spring joins masses " + std::to_string(e.a) + " and " + std::to_string(e.b) +
                                    " of " + std::to_string(massCount));
        }
        ++adjacency.offsets[std::size_t(e.a) + 1];
        ++adjacency.offsets[std::size_t(e.b) + 1];
    }
    for (std::size_t i = 0; i < massCount; ++i)
    {
        adjacency.offsets[i + 1] += adjacency.offsets[i];
    }
    adjacency.entries.resize(adjacency.offsets[massCount]);
    std::vector<std::size_t> next(adjacency.offsets.begin(), adjacency.offsets.end() - 1);
    for (std::size_t s = 0; s < ends.size(); ++s)
    {
        adjacency.entries[next[ends[s].a]++] = {ends[s].b, Index(s)};
        adjacency.entries[next[ends[s].b]++] = {ends[s].a, Index(s)};
    }
    return adjacency;
}
} // namespace masse
