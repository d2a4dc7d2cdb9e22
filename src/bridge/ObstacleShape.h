#pragma once
/// The solid an obstacle is, in its own frame: what ObstacleGeometry builds its collision shape and faces from. The
/// scene layer makes one from a scene file's description (reading a mesh's file); tests make them directly.

#include "MeshFile.h"

#include "core/Types.h"

#include <vector>

namespace masse::bridge
{
enum class ShapeKind
{
    Box,   ///< halfExtents
    Prism, ///< triangular prism: a triangle in the local x-y plane extruded along z
    Hull,  ///< convex hull of hullPoints
    Mesh,  ///< the polygons of `mesh` (may be concave)
};

struct ObstacleShape
{
    ShapeKind kind = ShapeKind::Box;
    Vec3 halfExtents = Vec3(0.5, 0.5, 0.5); ///< m (Box)
    /// Prism: base width along x, height along y, length along z, and the apex's x offset from the centre. The
    /// triangle (-w/2, -h/2), (w/2, -h/2), (apex, h/2) is extruded from z = -length/2 to +length/2.
    Real prismWidth = 1;
    Real prismHeight = 1;
    Real prismLength = 1;
    Real prismApex = 0;
    std::vector<Vec3> hullPoints; ///< m (Hull)
    PolygonMesh mesh;             ///< m, in the obstacle's frame (Mesh)
};
} // namespace masse::bridge
