#pragma once
/// Coarsening a sheet for the multigrid: masses are grouped into aggregates (a mass with its neighbours), and
/// aggregates into coarser ones.
///
/// Aggregates follow the planar springs only, so that each stays within one layer: a coarse level then keeps the
/// sheet's layers apart, and a bend (the layers stretching against each other) is a smooth coarse motion there,
/// where an aggregate through the thickness could only move both layers alike and would make a bend cost shear.
/// The interpolation between levels is built from these groups by MultigridPreconditioner.

#include "core/Types.h"
#include "core/lattice/SpringSet.h"

#include <cstdint>
#include <vector>

namespace masse
{
/// An undirected graph of nodes (masses or aggregates): the neighbours of node i are
/// neighbour[start[i]..start[i + 1]), ascending, without i itself.
struct NodeGraph
{
    std::vector<std::uint32_t> start;
    std::vector<std::uint32_t> neighbour;

    std::size_t nodes() const { return start.empty() ? 0 : start.size() - 1; }
};

/// The masses joined by planar springs.
NodeGraph planarGraph(const SpringSet& springs, std::size_t masses);

/// Groups the graph's nodes into aggregates, in node order (the same groups every time): each node whose neighbours
/// are all free starts an aggregate with them; a node left over joins a neighbour's aggregate; what is still left
/// groups with its free neighbours. Returns each node's aggregate; `count` receives their number.
std::vector<std::uint32_t> aggregate(const NodeGraph& graph, std::uint32_t& count);

/// The graph of the aggregates: two are neighbours when an edge joins their members.
NodeGraph contract(const NodeGraph& graph, const std::vector<std::uint32_t>& aggregateOf, std::uint32_t count);

} // namespace masse
