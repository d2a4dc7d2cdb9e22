#pragma once
/// Where a kinematic obstacle is, and how fast it moves, along its path of keys.

#include "ObstacleSpec.h"

namespace masse::bridge
{
struct Pose
{
    Vec3 position = Vec3::Zero();
    Eigen::Quaternion<Real> orientation = Eigen::Quaternion<Real>::Identity();
};

struct Motion
{
    Vec3 linear = Vec3::Zero();  ///< m/s of the local origin
    Vec3 angular = Vec3::Zero(); ///< rad/s
    /// Velocity of a point of the moving body.
    Vec3 at(const Vec3& point, const Vec3& origin) const { return linear + angular.cross(point - origin); }
};

/// The pose at time t (an empty path gives the spec's own pose).
Pose poseAt(const ObstacleSpec& spec, Real t);
/// The velocity at time t: that of the path segment containing t, zero before the first and after the last key.
Motion motionAt(const ObstacleSpec& spec, Real t);
/// The mean velocity from t0 to t1 (> t0): the pose change over the interval, so a motion that starts or stops
/// within it is not missed.
Motion averageMotion(const ObstacleSpec& spec, Real t0, Real t1);
} // namespace masse::bridge
