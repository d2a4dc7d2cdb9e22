#include "ObstacleProbe.h"

#include "BulletEnvironment.h"

namespace masse::bridge
{
std::vector<Real> signedDistances(BulletEnvironment& environment, const std::vector<Vec3>& points, Real searchDistance)
{
    std::vector<Real> out(points.size());
    for (std::size_t i = 0; i < points.size(); ++i)
    {
        out[i] = environment.nearestSurface(points[i], searchDistance).distance;
    }
    return out;
}

ObstacleQuery obstacleQuery(BulletEnvironment& environment)
{
    constexpr Real probeRadius = 1e-6;
    return {[&environment](const Vec3& from, const Vec3& to)
            { return environment.sweep(from, to, probeRadius).has_value(); }};
}
} // namespace masse::bridge
