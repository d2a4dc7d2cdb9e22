#pragma once
/// Vacuum and pressure forming in a scene: the "forming" section, the pressure schedule across the sheet and the
/// mould it seals against (its reports are in scene/reports/). Keys, units and defaults: data/scenes/README.md.

#include "core/material/PressureLoad.h"

#include <string>
#include <vector>

namespace masse::scene
{
class JsonObject;

struct FormingSpec
{
    bool enabled = false;
    /// Pa against s, above minus below: p > 0 presses the sheet down toward its underside (core/PressureLoad.h).
    std::vector<PressureKey> pressure;
    /// Pressure stops on triangles whose masses all touch an obstacle (the sheet has closed onto the mould).
    bool seal = true;
    /// The obstacle the sheet is clamped over and seals against ("": none named); a mesh must be a closed surface.
    std::string mould;
};

/// Reads the scene's "forming" object; throws InputError naming the key.
FormingSpec readForming(const JsonObject& o);
} // namespace masse::scene
