#pragma once
/// The solid an obstacle is, in its own frame, in the three forms Bullet is given: a convex polyhedron, the convex hull
/// of points, or a polygon mesh. The bridge knows no named shapes: each shape a scene file names (src/scene/shapes/)
/// makes one of these, so that a new shape adds nothing here; tests make them directly.

#include "MeshFile.h"

#include "core/Types.h"

#include <vector>

namespace masse::bridge
{
enum class SolidKind
{
    Polyhedron, ///< convex: `polygons`, each face turned outward, numbered in the order given
    Hull,       ///< convex hull of `hullPoints`, its faces as Bullet's hull computer finds them
    Mesh,       ///< `polygons` as given (may be concave, the winding taken as outward), numbered in their order
};

struct ObstacleShape
{
    SolidKind kind = SolidKind::Polyhedron;
    PolygonMesh polygons;         ///< m (Polyhedron, Mesh)
    std::vector<Vec3> hullPoints; ///< m (Hull)
};
} // namespace masse::bridge
