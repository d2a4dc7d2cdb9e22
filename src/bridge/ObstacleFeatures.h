#pragma once
/// The sharp features of an obstacle, in its own frame: the edges where two faces meet at a convex angle (a ridge a
/// sheet can fold over) and the corners where such edges end. The sheet's edge contact (core/EdgeContact.h) tests its
/// edges and triangles against these; edges between faces in one plane (a mesh's flat parts, split into triangles) and
/// concave edges (a mould's inner creases: a sheet edge spanning one stays outside both faces) are left out.

#include "ObstacleGeometry.h"

#include <vector>

namespace masse::bridge
{
struct SharpEdge
{
    int start = 0; ///< into ObstacleGeometry::vertices
    int end = 0;
    /// Outward normals of the two faces meeting at it; an open mesh's rim (one face) has the second reversed.
    Vec3 normals[2] = {Vec3::UnitY(), Vec3::UnitY()};
};

struct SharpCorner
{
    int vertex = 0;
    std::size_t firstNormal = 0; ///< its faces' outward normals: SharpFeatures::cornerNormals[first, first + count)
    std::size_t normalCount = 0;
};

struct SharpFeatures
{
    std::vector<SharpEdge> edges;
    std::vector<SharpCorner> corners;
    std::vector<Vec3> cornerNormals;
};

/// The faces' outward normals decide what is convex; a mesh is taken as wound outward, as its contact takes it
/// (a mesh wound inside out has its ridges taken for creases, and gets no edge contact).
SharpFeatures sharpFeatures(const ObstacleGeometry& geometry);
} // namespace masse::bridge
