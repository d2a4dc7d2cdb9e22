#include "scene/Room.h"

#include "scene/shapes/BoxShape.h"

#include "core/Format.h"
#include "core/InputError.h"

#include <cmath>

namespace masse::scene
{
void validate(const RoomSpec& room)
{
    for (int axis = 0; axis < 3; ++axis)
    {
        if (!std::isfinite(room.minCorner[axis]) || !std::isfinite(room.maxCorner[axis]) ||
            !(room.maxCorner[axis] > room.minCorner[axis]))
        {
            throw InputError("environment.room.max: must exceed min on every axis");
        }
    }
    if (!(room.wallThickness > 0))
    {
        throw InputError("environment.room.wall_thickness: must be > 0 m (got " + formatNumber(room.wallThickness) +
                         ")");
    }
}

std::vector<ObstacleSpec> roomObstacles(const RoomSpec& room)
{
    validate(room);
    const Vec3 lo = room.minCorner;
    const Vec3 hi = room.maxCorner;
    const Real t = room.wallThickness;
    const Vec3 centre = 0.5 * (lo + hi);
    const Vec3 half = 0.5 * (hi - lo) + Vec3(t, t, t); // walls overlap at the corners, leaving no gap
    auto wall = [&](const char* name, int axis, bool high)
    {
        ObstacleSpec spec;
        spec.name = name;
        Vec3 wallHalf = half;
        wallHalf[axis] = t / 2;
        spec.shape = boxShapeSpec(wallHalf);
        spec.position = centre;
        spec.position[axis] = high ? hi[axis] + t / 2 : lo[axis] - t / 2;
        return spec;
    };
    return {wall("floor", 1, false),     wall("ceiling", 1, true),    wall("wall_left", 0, false),
            wall("wall_right", 0, true), wall("wall_back", 2, false), wall("wall_front", 2, true)};
}

void addRoom(bridge::BulletEnvironment& environment, const RoomSpec& room)
{
    if (!room.enabled)
    {
        return;
    }
    for (const ObstacleSpec& wall : roomObstacles(room))
    {
        environment.addObstacle(obstacleBody(wall), true);
    }
}
} // namespace masse::scene
