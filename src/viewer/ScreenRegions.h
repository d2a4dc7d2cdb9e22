#pragma once
/// Where the sheet and each obstacle appear in the window, written beside a screenshot so a test can look for the
/// paper's colours where they belong (red and green masses on the sheet, a black face on the obstacle touched).

#include "Camera.h"

#include "scene/Scene.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <vector>

namespace masse::viewer
{
/// A rectangle of the window in pixels from the top-left corner.
struct ScreenBox
{
    Real left = 0;
    Real top = 0;
    Real right = 0;
    Real bottom = 0;
};

/// The rectangle covering the projected points, clipped to the window; nothing if a point is behind the eye (its
/// projection is meaningless) or the rectangle misses the window.
std::optional<ScreenBox> screenBox(const OrbitCamera& camera, const Viewport& viewport,
                                   const std::vector<Vec3>& points);

/// {"width", "height", "sheet": [left, top, right, bottom] or null, "obstacles": [{"name", "box", "touched"}]} for the
/// scene's polyhedra (not the room); "touched" is true when a mass touched one of its faces during the last step.
/// The window's --regions file adds "scene" and "panel" (the view's and the side column's rectangles, the panel null
/// without UI) and gives the whole window's "width" and "height".
nlohmann::json screenRegions(scene::Scene& scene, const OrbitCamera& camera, const Viewport& viewport);

/// Whether every point projects inside the viewport (nothing clipped at its edges, nothing behind the eye).
bool wholeInView(const OrbitCamera& camera, const Viewport& viewport, const std::vector<Vec3>& points);

struct SceneSnapshot;
/// The same from a snapshot (what the window drew), with "sheet_whole": whether all of the sheet is in the view.
nlohmann::json screenRegions(const SceneSnapshot& snapshot, const OrbitCamera& camera, const Viewport& viewport);

/// World positions of an obstacle's vertices where it is now.
std::vector<Vec3> obstacleVertices(const bridge::Obstacle& obstacle);
} // namespace masse::viewer
