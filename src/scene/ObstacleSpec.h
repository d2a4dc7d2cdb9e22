#pragma once
/// The description of one obstacle (a polyhedron in the paper's room), as a scene file gives it, and the bridge's
/// obstacle made from it. Its shape is one of the registered shapes (scene/shapes/ShapeRegistry.h) with the
/// parameters that shape's reader made.

#include "scene/shapes/BoxShape.h"

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

    /// Its shape; the solid is made from it by obstacleBody (a mesh's file is read then). A spec built in code without
    /// one is a box a metre across, so that every obstacle has a registered shape.
    ShapeSpec shape = boxShapeSpec(Vec3(0.5, 0.5, 0.5));

    /// A kinematic obstacle follows its path; with no keys it is static.
    std::vector<bridge::PoseKey> path;
    bool isKinematic() const { return !path.empty(); }
};

/// Rotation from angles in degrees about x, then y, then z (each about the room's fixed axes): the scene file's
/// "rotation_deg".
Eigen::Quaternion<Real> rotationFromDegrees(const Vec3& degrees);

/// The bridge's obstacle for a spec: its shape's solid (a mesh read from its file, scaled) and its pose and path.
/// Throws InputError naming the obstacle and the file for a mesh that will not load.
bridge::ObstacleBody obstacleBody(const ObstacleSpec& spec);
} // namespace masse::scene
