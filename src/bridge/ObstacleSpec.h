#pragma once
/// The description of one obstacle (a polyhedron in the paper's room), as a scene file gives it.

#include "core/Types.h"

#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace masse::bridge
{
enum class ObstacleKind
{
    Box,   ///< half extents
    Prism, ///< triangular prism: a triangle in the local x-y plane extruded along z
    Hull,  ///< convex hull of given points (local coordinates)
    Mesh,  ///< triangle mesh from an OBJ file (may be concave)
};

/// One key of a kinematic obstacle's path: where it is at a time. Between keys the position is interpolated
/// linearly and the orientation by slerp; before the first and after the last key the obstacle stays put.
struct PathKey
{
    Real time = 0;                ///< s
    Vec3 position = Vec3::Zero(); ///< m
    Eigen::Quaternion<Real> orientation = Eigen::Quaternion<Real>::Identity();
};

struct ObstacleSpec
{
    std::string name;
    ObstacleKind kind = ObstacleKind::Box;
    Vec3 position = Vec3::Zero();                                              ///< m, local origin in the room
    Eigen::Quaternion<Real> orientation = Eigen::Quaternion<Real>::Identity(); ///< local to room

    Vec3 halfExtents = Vec3(0.5, 0.5, 0.5); ///< m (Box)
    /// Prism: base width along x, height along y, length along z, and the apex's x offset from the centre. The
    /// triangle (-w/2, -h/2), (w/2, -h/2), (apex, h/2) is extruded from z = -length/2 to +length/2.
    Real prismWidth = 1;
    Real prismHeight = 1;
    Real prismLength = 1;
    Real prismApex = 0;
    std::vector<Vec3> hullPoints; ///< m (Hull)
    std::string meshPath;         ///< OBJ file (Mesh); relative paths are resolved by the scene loader
    Real meshScale = 1;           ///< applied to the OBJ's coordinates (Mesh)

    /// A kinematic obstacle follows its path; with no keys it is static.
    std::vector<PathKey> path;
    bool isKinematic() const { return !path.empty(); }
};

/// Rotation from angles in degrees about x, then y, then z (each about the room's fixed axes).
Eigen::Quaternion<Real> rotationFromDegrees(const Vec3& degrees);
} // namespace masse::bridge
