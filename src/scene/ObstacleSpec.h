#pragma once
/// The description of one obstacle (a polyhedron in the paper's room), as a scene file gives it, and the bridge's
/// obstacle made from it. Its solid is the bridge's own ObstacleShape, so a shape's parameters are declared once.

#include "bridge/BulletEnvironment.h"

#include "core/Types.h"

#include <Eigen/Geometry>

#include <string>
#include <vector>

namespace masse::scene
{
struct ObstacleSpec
{
    std::string name;
    Vec3 position = Vec3::Zero();                                              ///< m, local origin in the room
    Eigen::Quaternion<Real> orientation = Eigen::Quaternion<Real>::Identity(); ///< local to room

    /// The solid in its own frame; a Mesh's polygons stay empty here and are read from meshPath by obstacleBody.
    bridge::ObstacleShape shape;
    std::string meshPath; ///< OBJ or STL file (Mesh); relative paths are resolved by the scene loader
    Real meshScale = 1;   ///< applied to the file's coordinates (Mesh)

    /// A kinematic obstacle follows its path; with no keys it is static.
    std::vector<bridge::PoseKey> path;
    bool isKinematic() const { return !path.empty(); }
};

/// Rotation from angles in degrees about x, then y, then z (each about the room's fixed axes): the scene file's
/// "rotation_deg".
Eigen::Quaternion<Real> rotationFromDegrees(const Vec3& degrees);

/// The bridge's obstacle for a spec: its solid (a mesh read from its file, scaled) and its pose and path. Throws
/// InputError naming the obstacle and the file for a mesh that will not load.
bridge::ObstacleBody obstacleBody(const ObstacleSpec& spec);
} // namespace masse::scene
