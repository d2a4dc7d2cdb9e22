#pragma once
/// The box: `obstacles[].type` "box", half its extents along its own axes. Declared here for what builds boxes in code
/// (the room's walls, tests).

#include "scene/shapes/ShapeRegistry.h"

namespace masse::scene
{
/// A box's solid: its eight corners and six faces, numbered 0 +x, 1 -x, 2 +y (top), 3 -y (bottom), 4 +z, 5 -z.
/// Throws InputError naming the axis ("halfExtents.y") of a half extent that is not a positive number.
bridge::ObstacleShape boxSolid(const Vec3& halfExtents);

/// A box as a scene holds it.
ShapeSpec boxShapeSpec(const Vec3& halfExtents);
} // namespace masse::scene
