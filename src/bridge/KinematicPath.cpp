#include "KinematicPath.h"

#include <cmath>

namespace masse::bridge
{
namespace
{
/// Index k of the segment [key k, key k + 1] containing t, or -1 outside the path.
int segmentAt(const std::vector<PathKey>& path, Real t)
{
    for (std::size_t k = 0; k + 1 < path.size(); ++k)
    {
        if (t >= path[k].time && t < path[k + 1].time)
        {
            return int(k);
        }
    }
    return -1;
}
} // namespace

Pose poseAt(const ObstacleSpec& spec, Real t)
{
    const std::vector<PathKey>& path = spec.path;
    if (path.empty())
    {
        return {spec.position, spec.orientation};
    }
    if (t <= path.front().time)
    {
        return {path.front().position, path.front().orientation};
    }
    const int k = segmentAt(path, t);
    if (k < 0)
    {
        return {path.back().position, path.back().orientation};
    }
    const PathKey& a = path[std::size_t(k)];
    const PathKey& b = path[std::size_t(k) + 1];
    const Real s = (t - a.time) / (b.time - a.time);
    return {a.position + s * (b.position - a.position), a.orientation.slerp(s, b.orientation)};
}

Motion averageMotion(const ObstacleSpec& spec, Real t0, Real t1)
{
    Motion motion;
    const Pose a = poseAt(spec, t0);
    const Pose b = poseAt(spec, t1);
    motion.linear = (b.position - a.position) / (t1 - t0);
    const Eigen::AngleAxis<Real> turn(b.orientation * a.orientation.inverse());
    motion.angular = turn.axis() * (turn.angle() / (t1 - t0));
    if (!motion.angular.allFinite())
    {
        motion.angular.setZero();
    }
    return motion;
}

Motion motionAt(const ObstacleSpec& spec, Real t)
{
    Motion motion;
    const int k = segmentAt(spec.path, t);
    if (k < 0)
    {
        return motion;
    }
    const PathKey& a = spec.path[std::size_t(k)];
    const PathKey& b = spec.path[std::size_t(k) + 1];
    const Real duration = b.time - a.time;
    motion.linear = (b.position - a.position) / duration;
    const Eigen::AngleAxis<Real> turn(b.orientation * a.orientation.inverse());
    motion.angular = turn.axis() * (turn.angle() / duration);
    if (!motion.angular.allFinite())
    {
        motion.angular.setZero();
    }
    return motion;
}
} // namespace masse::bridge
