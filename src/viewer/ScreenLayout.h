#pragma once
/// Where things go in the window: the scene's view on the left, and a side column on the right for the HUD, the
/// colour bar and the panel. The column is docked beside the view rather than floating over it, so neither the panel
/// nor the HUD ever covers the sheet: the camera frames the sheet in the view's own rectangle. No GL.

#include "Camera.h"

namespace masse::viewer
{
/// A rectangle of the window in pixels, from its top-left corner (y down, as mouse events give it).
struct ScreenRect
{
    int x = 0;
    int y = 0;
    int width = 0;
    int height = 0;
    int right() const { return x + width; }
    int bottom() const { return y + height; }
    bool overlaps(const ScreenRect& other) const
    {
        return x < other.right() && other.x < right() && y < other.bottom() && other.y < bottom();
    }
};

struct ScreenLayout
{
    ScreenRect window;
    ScreenRect scene;  ///< the 3D view; starts at the window's top-left, so mouse positions need no offset
    ScreenRect column; ///< the side column (width 0 without UI)
    /// The scene's rectangle as the camera's viewport.
    Viewport sceneViewport() const { return {scene.width, scene.height}; }
};

/// px, the column's width when the window is wide enough (its fields and labels fit); never more than
/// `maxColumnShare` of the window.
inline constexpr int columnWidth = 360;
inline constexpr double maxColumnShare = 0.5;

/// The layout of a window of the given size; `showUi` false gives the scene the whole window (clean captures).
ScreenLayout screenLayout(int windowWidth, int windowHeight, bool showUi);
} // namespace masse::viewer
