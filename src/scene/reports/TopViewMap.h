#pragma once
/// A scalar of the sheet drawn as a map seen from above, with a colour bar: the thickness and temperature maps and
/// `masse converge`'s error band.

#include "scene/Scene.h"
#include "scene/output/Plot.h"

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

/// Draws `perMass` on the scene's sheet seen from above into `pngPath` (report.thickness_map.pixels wide), through a
/// data file beside it that is removed once drawn, whatever happens; the drawing is one of `plots`.
void drawTopViewMap(PlotBatch& plots, const Scene& scene, const std::vector<Real>& perMass, const std::string& pngPath,
                    const std::string& title, const std::string& subtitle, const std::string& unitLabel,
                    const std::string& palette, const std::vector<Real>& colourRange = {});
} // namespace masse::scene
