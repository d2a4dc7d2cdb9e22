#include "scene/ObstacleSpec.h"

#include <cmath>

namespace masse::scene
{
Eigen::Quaternion<Real> rotationFromDegrees(const Vec3& degrees)
{
    const Vec3 radians = degrees * (M_PI / 180.0);
    return Eigen::Quaternion<Real>(Eigen::AngleAxis<Real>(radians.z(), Vec3::UnitZ()) *
                                   Eigen::AngleAxis<Real>(radians.y(), Vec3::UnitY()) *
                                   Eigen::AngleAxis<Real>(radians.x(), Vec3::UnitX()));
}

bridge::ObstacleBody obstacleBody(const ObstacleSpec& spec)
{
    bridge::ObstacleBody body;
    body.name = spec.name;
    body.path.rest = {spec.position, spec.orientation};
    body.path.keys = spec.path;
    body.shape = spec.shape.solid(spec.name);
    return body;
}
} // namespace masse::scene
