// obstacles[].type "hull": the convex hull of `points` (at least four, not all in one plane), in the obstacle's frame.
// Its faces are numbered as Bullet's convex-hull computer finds them.

#include "scene/shapes/ShapeRegistry.h"

#include "scene/PlausibleRanges.h"

#include <algorithm>

namespace masse::scene
{
namespace
{
struct HullPoints
{
    std::vector<Vec3> points; ///< m
};

std::any readHull(const JsonObject& o, const std::string& /*baseDirectory*/)
{
    HullPoints hull{o.vec3List("points")};
    for (const Vec3& p : hull.points)
    {
        plausible::checkPoint(o, "points", p);
    }
    return hull;
}

bridge::ObstacleShape hullSolid(const std::any& parameters, const std::string& /*obstacle*/)
{
    bridge::ObstacleShape solid;
    solid.kind = bridge::SolidKind::Hull;
    solid.hullPoints = std::any_cast<const HullPoints&>(parameters).points;
    return solid;
}

Real hullReach(const std::any& parameters)
{
    Real reach = 0;
    for (const Vec3& p : std::any_cast<const HullPoints&>(parameters).points)
    {
        reach = std::max(reach, p.norm());
    }
    return reach;
}
} // namespace

extern const ShapeEntry hullShape = {
    .name = "hull",
    .closed = true,
    .read = readHull,
    .solid = hullSolid,
    .reach = hullReach,
};
} // namespace masse::scene
