#include "KinematicPath.h"

#include <cmath>

namespace masse::bridge
{
namespace
{
/// Index k of the segment [key k, key k + 1] containing t, or -1 outside the path.
int segmentAt(const std::vector<PoseKey>& path, Real t)
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

Pose poseAt(const KinematicPath& kinematic, Real t)
{
    const std::vector<PoseKey>& path = kinematic.keys;
    if (path.empty())
    {
        return kinematic.rest;
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
    const PoseKey& a = path[std::size_t(k)];
    const PoseKey& b = path[std::size_t(k) + 1];
    const Real s = (t - a.time) / (b.time - a.time);
    return {a.position + s * (b.position - a.position), a.orientation.slerp(s, b.orientation)};
}

Motion averageMotion(const KinematicPath& path, Real t0, Real t1)
{
    Motion motion;
    const Pose a = poseAt(path, t0);
    const Pose b = poseAt(path, t1);
    motion.linear = (b.position - a.position) / (t1 - t0);
    const Eigen::AngleAxis<Real> turn(b.orientation * a.orientation.inverse());
    motion.angular = turn.axis() * (turn.angle() / (t1 - t0));
    if (!motion.angular.allFinite())
    {
        motion.angular.setZero();
    }
    return motion;
}

Motion motionAt(const KinematicPath& path, Real t)
{
    Motion motion;
    const int k = segmentAt(path.keys, t);
    if (k < 0)
    {
        return motion;
    }
    const PoseKey& a = path.keys[std::size_t(k)];
    const PoseKey& b = path.keys[std::size_t(k) + 1];
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
