#pragma once
/// Conversions between the core's Eigen types and Bullet's. MaSSE links Bullet's float64 build (pkg-config
/// bullet-float64, BT_USE_DOUBLE_PRECISION) on purpose: the core is double precision, so positions cross the bridge
/// without rounding and contact tolerances of micrometres stay meaningful.

#include "core/Types.h"

#include <Eigen/Geometry>
#include <LinearMath/btQuaternion.h>
#include <LinearMath/btTransform.h>
#include <LinearMath/btVector3.h>

static_assert(sizeof(btScalar) == sizeof(double), "MaSSE needs Bullet's double-precision build (bullet-float64)");

namespace masse::bridge
{
using Quat = Eigen::Quaternion<Real>;

inline btVector3 toBullet(const Vec3& v)
{
    return btVector3(v.x(), v.y(), v.z());
}
inline Vec3 toVec3(const btVector3& v)
{
    return Vec3(v.x(), v.y(), v.z());
}
inline btQuaternion toBullet(const Quat& q)
{
    return btQuaternion(q.x(), q.y(), q.z(), q.w());
}
inline btTransform toBullet(const Vec3& position, const Quat& orientation)
{
    return btTransform(toBullet(orientation), toBullet(position));
}
} // namespace masse::bridge
