#pragma once
/// The paper's room (Table 1): floor at y = -2.81, walls at x = -6.5 and 6.5, z = -2.99 (back) and 3.33, ceiling at
/// y = 3.0. Each is a static box one metre thick lying outside the room, so masses meet its inner face. The scene
/// file's "environment.room".

#include "scene/ObstacleSpec.h"

#include "bridge/BulletEnvironment.h"

namespace masse::scene
{
struct RoomSpec
{
    bool enabled = true;
    Vec3 minCorner = Vec3(-6.5, -2.81, -2.99); ///< m
    Vec3 maxCorner = Vec3(6.5, 3.0, 3.33);     ///< m
    Real wallThickness = 1.0;                  ///< m
};

/// Throws InputError naming the key (environment.room.max, wall_thickness) unless max exceeds min on every axis and
/// the thickness is positive.
void validate(const RoomSpec& room);

/// The room's boxes, named floor, ceiling, wall_left (-x), wall_right (+x), wall_back (-z), wall_front (+z).
std::vector<ObstacleSpec> roomObstacles(const RoomSpec& room);

/// Adds the room's boxes to the environment, marked as part of the room (nothing when the room is off).
void addRoom(bridge::BulletEnvironment& environment, const RoomSpec& room);
} // namespace masse::scene
