#pragma once
/// Vacuum and pressure forming in a scene: the "forming" section (the pressure schedule across the sheet and the
/// mould it seals against) and the forming reports under "report" (thickness and temperature maps, the per-mass CSV,
/// the share of thin area). Keys, units and defaults: data/scenes/README.md.

#include "core/material/PressureLoad.h"

#include <string>

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

/// Forming reports written by `masse run` (beside ReportSpec's section and sag).
struct FormingReportSpec
{
    bool thicknessMap = false;   ///< thickness_map.png, top view with a colour bar
    bool temperatureMap = false; ///< temperature_map.png (needs heat)
    bool massesCsv = false;      ///< masses.csv: position, thickness, temperature, contact of every mass
    Real thinBelow = 0.5;        ///< h / h0 under which area counts as thin (summary: thin_area_share)
    int mapPixels = 900;         ///< width of the maps in pixels
    /// h / h0 at the thickness map's colour bar's ends: fixed, so that maps of two runs compare and a 6% thinning
    /// does not span the whole bar; a thickness beyond them takes the end's colour.
    Real mapRangeLow = 0;
    Real mapRangeHigh = 1;
};

/// Reads the scene's "forming" object; throws InputError naming the key.
FormingSpec readForming(const JsonObject& o);
/// Reads the forming keys of the "report" object (thickness_map, temperature_map, masses_csv); the caller finishes it.
FormingReportSpec readFormingReport(const JsonObject& report);
} // namespace masse::scene
