#include "core/linear/Aggregation.h"

#include <algorithm>
#include <limits>

namespace masse
{
namespace
{
constexpr std::uint32_t unassigned = std::numeric_limits<std::uint32_t>::max();

/// A graph from an edge list of (a, b) pairs, each edge listed once or more in either direction.
NodeGraph graphFromEdges(std::size_t nodes, std::vector<std::pair<std::uint32_t, std::uint32_t>>& edges)
{
    NodeGraph graph;
    graph.start.assign(nodes + 1, 0);
    std::vector<std::pair<std::uint32_t, std::uint32_t>> both;
    both.reserve(2 * edges.size());
    for (const auto& [a, b] : edges)
    {
        if (a != b)
        {
            both.emplace_back(a, b);
            both.emplace_back(b, a);
        }
    }
    std::sort(both.begin(), both.end());
    both.erase(std::unique(both.begin(), both.end()), both.end());
    graph.neighbour.reserve(both.size());
    for (const auto& [a, b] : both)
    {
        ++graph.start[a + 1];
        graph.neighbour.push_back(b);
    }
    for (std::size_t i = 0; i < nodes; ++i)
    {
        graph.start[i + 1] += graph.start[i];
    }
    return graph;
}
} // namespace

NodeGraph planarGraph(const SpringSet& springs, std::size_t masses)
{
    std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
    edges.reserve(springs.size());
    for (std::size_t s = 0; s < springs.size(); ++s)
    {
        if (springs.classes()[s] == SpringClass::Planar)
        {
            edges.emplace_back(springs.ends()[s].a, springs.ends()[s].b);
        }
    }
    return graphFromEdges(masses, edges);
}

std::vector<std::uint32_t> aggregate(const NodeGraph& graph, std::uint32_t& count)
{
    const std::size_t n = graph.nodes();
    std::vector<std::uint32_t> aggregateOf(n, unassigned);
    count = 0;
    auto neighbours = [&](std::size_t i)
    { return std::pair(graph.neighbour.begin() + graph.start[i], graph.neighbour.begin() + graph.start[i + 1]); };
    for (std::size_t i = 0; i < n; ++i)
    {
        if (aggregateOf[i] != unassigned)
        {
            continue;
        }
        const auto [begin, end] = neighbours(i);
        if (std::any_of(begin, end, [&](std::uint32_t j) { return aggregateOf[j] != unassigned; }))
        {
            continue;
        }
        aggregateOf[i] = count;
        for (auto j = begin; j != end; ++j)
        {
            aggregateOf[*j] = count;
        }
        ++count;
    }
    // Left-over nodes join the aggregate of their first neighbour that had one after the first pass (not one that
    // joined in this pass, so aggregates do not grow in chains).
    std::vector<std::uint32_t> joined = aggregateOf;
    for (std::size_t i = 0; i < n; ++i)
    {
        if (aggregateOf[i] != unassigned)
        {
            continue;
        }
        const auto [begin, end] = neighbours(i);
        const auto found = std::find_if(begin, end, [&](std::uint32_t j) { return aggregateOf[j] != unassigned; });
        if (found != end)
        {
            joined[i] = aggregateOf[*found];
        }
    }
    aggregateOf = std::move(joined);
    for (std::size_t i = 0; i < n; ++i)
    {
        if (aggregateOf[i] != unassigned)
        {
            continue;
        }
        aggregateOf[i] = count;
        const auto [begin, end] = neighbours(i);
        for (auto j = begin; j != end; ++j)
        {
            if (aggregateOf[*j] == unassigned)
            {
                aggregateOf[*j] = count;
            }
        }
        ++count;
    }
    return aggregateOf;
}

NodeGraph contract(const NodeGraph& graph, const std::vector<std::uint32_t>& aggregateOf, std::uint32_t count)
{
    std::vector<std::pair<std::uint32_t, std::uint32_t>> edges;
    edges.reserve(graph.neighbour.size() / 2);
    for (std::size_t i = 0; i < graph.nodes(); ++i)
    {
        for (std::uint32_t k = graph.start[i]; k < graph.start[i + 1]; ++k)
        {
            const std::uint32_t j = graph.neighbour[k];
            if (j > i && aggregateOf[i] != aggregateOf[j])
            {
                edges.emplace_back(aggregateOf[i], aggregateOf[j]);
            }
        }
    }
    return graphFromEdges(count, edges);
}

} // namespace masse
