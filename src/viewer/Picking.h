#pragma once
/// Mouse picking math (paper section 7): the ray through a pixel, the mass nearest the camera among those within a
/// pixel tolerance of that ray, and the plane a picked mass is dragged on. No GL, so the tests check it directly.

#include "Camera.h"

#include <optional>
#include <vector>

namespace masse::viewer
{
struct Ray
{
    Vec3 origin = Vec3::Zero();
    Vec3 direction = Vec3::UnitZ(); ///< unit
};

/// The ray from the eye through a point of the window (pixels from the top-left corner, y down; a pixel's centre is
/// at +0.5).
Ray rayThroughPixel(const OrbitCamera& camera, const Viewport& viewport, Real x, Real y);

struct MassPick
{
    Index mass = 0;
    Real depth = 0;       ///< m along the ray
    Real pixelOffset = 0; ///< how far from the ray it appears, in pixels
};

/// Among the masses that appear within `tolerancePixels` of the ray, the one nearest the eye (the one the user sees
/// under the cursor); nothing if none is that close or all are behind the eye. `pixelSizeAtUnitDepth` converts
/// pixels to metres per metre of depth (OrbitCamera::pixelSizeAtUnitDepth).
std::optional<MassPick> pickNearestMass(const std::vector<Vec3>& positions, const Ray& ray, Real pixelSizeAtUnitDepth,
                                        Real tolerancePixels);

/// The plane a picked mass is dragged on: through the mass, facing the camera, so the cursor moves the target
/// across the screen at the mass's depth.
struct DragPlane
{
    Vec3 point = Vec3::Zero();
    Vec3 normal = Vec3::UnitZ(); ///< unit
};

DragPlane dragPlaneFacing(const OrbitCamera& camera, const Vec3& through);

/// Where the ray meets the plane; nothing if the ray runs parallel to it or the meeting point is behind the origin.
std::optional<Vec3> intersect(const Ray& ray, const DragPlane& plane);
} // namespace masse::viewer
