#pragma once
/// What a forming engineer reads from a run: the wall-thickness map seen from above (and the temperature map), every
/// mass in a CSV, and the share of the part that came out thinner than a threshold.

#include "scene/Scene.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace masse::scene
{
/// A scalar of the bottom layer drawn in top view (x across, z down the page as seen from +y), rasterised from the
/// layer's triangles with linear interpolation; where the surface overlaps itself in this view the highest wins.
struct TopViewMap
{
    int width = 0;
    int height = 0;
    Real minX = 0, maxX = 0, minZ = 0, maxZ = 0; ///< m, the area shown
    std::vector<Real> value;                     ///< width x height, row by row from minZ; NaN where no sheet
};

/// Rasterises `perMass` (one value per mass; only the bottom layer's are used) at `width` pixels across.
TopViewMap topViewMap(const Scene& scene, const std::vector<Real>& perMass, int width);

/// The gnuplot data (x z value, rows separated by blank lines) and script for a map with a colour bar labelled
/// `unitLabel`; `subtitle` goes under the title. The colour bar spans `colourRange` ({low, high}, in the values'
/// unit), or the values' own range when it is empty.
std::string mapData(const TopViewMap& map);
std::string mapPlotScript(const std::string& dataPath, const std::string& title, const std::string& subtitle,
                          const std::string& unitLabel, const std::string& palette,
                          const std::vector<Real>& colourRange = {});

/// Draws `perMass` on the scene's sheet seen from above into `pngPath` (the scene's map width), through a
/// data file beside it that is removed afterwards, whatever happens.
void drawTopViewMap(const Scene& scene, const std::vector<Real>& perMass, const std::string& pngPath,
                    const std::string& title, const std::string& subtitle, const std::string& unitLabel,
                    const std::string& palette, const std::vector<Real>& colourRange = {});

/// Share (0..1) of the bottom layer's current area whose thickness is below `ratio` times h0.
Real thinAreaShare(const SheetThickness& thickness, Real ratio);

/// Every mass: index, layer, position (m), thickness (m) and h/h0 (if a material), temperature (C, if heat) and the
/// obstacle it touched in the last frame ("" if none).
std::string massesCsv(Scene& scene);

/// The forming figures for summary.json: thickness min and where, thin area share, sealed area, pressure now.
nlohmann::json formingSummary(const Scene& scene);

/// Writes the reports the scene asks for (thickness_map.png, temperature_map.png, masses.csv) into `directory`.
void writeFormingReports(Scene& scene, const std::string& directory);
} // namespace masse::scene
