#pragma once
/// report.thickness_map: the wall thickness of the formed part seen from above (thickness_map.png), with the thinnest
/// place and the share of the area thinner than a threshold in its title. Its threshold and width serve the forming
/// summary and the other maps too.

#include "scene/SceneSpec.h"

#include "core/material/Thickness.h"

namespace masse::scene
{
struct ThicknessMapSettings
{
    bool drawn = false;   ///< thickness_map.png is drawn
    Real thinBelow = 0.5; ///< h / h0 under which area counts as thin (summary: thin_area_share)
    int pixels = 900;     ///< width of the maps in pixels
    /// h / h0 at the colour bar's ends: fixed, so that maps of two runs compare and a 6% thinning does not span the
    /// whole bar; a thickness beyond them takes the end's colour.
    Real rangeLow = 0;
    Real rangeHigh = 1;
};

/// What the scene's report.thickness_map says, its defaults when the scene does not name it.
ThicknessMapSettings thicknessMapSettings(const SceneSpec& spec);

/// Share (0..1) of the bottom layer's current area whose thickness is below `ratio` times h0.
Real thinAreaShare(const SheetThickness& thickness, Real ratio);
} // namespace masse::scene
