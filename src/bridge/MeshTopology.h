#pragma once
/// Whether a polygon mesh is a closed surface: every edge shared by exactly two faces. A female mould the sheet seals
/// against must be one, or its rim (and the cavity's wall) has a gap the air would pass through.

#include <optional>
#include <vector>

namespace masse::bridge
{
/// An edge between two vertices (0-based indices) and how many faces use it.
struct MeshEdge
{
    int a = 0;
    int b = 0;
    int faces = 0;
};

/// The first edge (smallest vertex pair) used by other than two faces, if any.
std::optional<MeshEdge> findOpenEdge(const std::vector<std::vector<int>>& faces);
} // namespace masse::bridge
