#pragma once
/// Where an obstacle is, and how fast it moves: at rest at one pose, or along a path of timed poses (a kinematic
/// obstacle).

#include "core/Types.h"

#include <Eigen/Geometry>

#include <vector>

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

/// One key of a path: where the obstacle is at a time. Between keys the position is interpolated linearly and the
/// orientation by slerp; before the first and after the last key the obstacle stays put.
struct PoseKey
{
    Real time = 0;                ///< s
    Vec3 position = Vec3::Zero(); ///< m
    Eigen::Quaternion<Real> orientation = Eigen::Quaternion<Real>::Identity();
};

struct KinematicPath
{
    Pose rest;                 ///< where the obstacle is while it has no keys
    std::vector<PoseKey> keys; ///< in increasing time
    /// A kinematic obstacle follows its keys; with none it is static.
    bool isKinematic() const { return !keys.empty(); }
};

/// The pose at time t (a path without keys gives its rest pose).
Pose poseAt(const KinematicPath& path, Real t);
/// The velocity at time t: that of the path segment containing t, zero before the first and after the last key.
Motion motionAt(const KinematicPath& path, Real t);
/// The mean velocity from t0 to t1 (> t0): the pose change over the interval, so a motion that starts or stops
/// within it is not missed.
Motion averageMotion(const KinematicPath& path, Real t0, Real t1);
} // namespace masse::bridge
