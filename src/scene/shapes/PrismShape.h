#pragma once
/// The triangular prism: `obstacles[].type` "prism", a triangle in its local x-y plane extruded along z. Declared here
/// for what builds prisms in code (tests).

#include "scene/shapes/ShapeRegistry.h"

namespace masse::scene
{
/// The triangle (-width/2, -height/2), (width/2, -height/2), (apex, height/2) extruded from z = -length/2 to
/// +length/2: apex is the top edge's x offset from the centre.
struct PrismSize
{
    Real width = 1;  ///< m, the base along x
    Real height = 1; ///< m, along y
    Real length = 1; ///< m, along z
    Real apex = 0;   ///< m
};

/// A prism's solid: six corners and five faces, numbered 0 base (-y), 1 side from the +x base corner to the apex, 2
/// side from the apex to the -x base corner, 3 end +z, 4 end -z. Throws InputError naming the size ("width") that is
/// not a positive number, or the apex that is not finite.
bridge::ObstacleShape prismSolid(const PrismSize& size);
} // namespace masse::scene
