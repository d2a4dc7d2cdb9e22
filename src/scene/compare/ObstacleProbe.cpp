#include "scene/compare/ObstacleProbe.h"

namespace masse::scene
{
std::vector<Real> signedDistances(ContactDetector& obstacles, const std::vector<Vec3>& points, Real searchDistance)
{
    std::vector<Real> out(points.size());
    for (std::size_t i = 0; i < points.size(); ++i)
    {
        out[i] = obstacles.nearestSurface(points[i], searchDistance).distance;
    }
    return out;
}

ObstacleQuery obstacleQuery(ContactDetector& obstacles)
{
    constexpr Real probeRadius = 1e-6;
    return {[&obstacles](const Vec3& from, const Vec3& to)
            { return obstacles.sweep(from, to, probeRadius).has_value(); }};
}
} // namespace masse::scene
