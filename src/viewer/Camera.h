#pragma once
/// The viewer's camera: it orbits a target point, as the paper's viewing environment flies around the room with the
/// mouse (section 7). Pure math, no GL: the renderer takes its matrices, picking its rays, the tests its numbers.

#include "core/Types.h"

#include <optional>
#include <string_view>

namespace masse::viewer
{
using Mat4 = Eigen::Matrix<Real, 4, 4>;
using Vec2 = Eigen::Matrix<Real, 2, 1>;

/// A window's drawable area in pixels.
struct Viewport
{
    int width = 1;
    int height = 1;
    Real aspect() const { return Real(width) / Real(height > 0 ? height : 1); }
};

/// Named viewpoints: the overview, and the paper's figures 8 (looking up through the sheet from below) and 9 (an
/// elevated left-side view).
enum class ViewPreset
{
    Overview,
    FromBelow,
    ElevatedLeft,
};

/// Parses "overview", "below" or "left"; throws InputError naming the allowed names.
ViewPreset parseViewPreset(std::string_view name);

class OrbitCamera
{
public:
    Vec3 target = Vec3::Zero();
    Real yaw = 0;                         ///< rad about +y; 0 puts the eye on the +z side of the target
    Real pitch = 0;                       ///< rad; positive puts the eye above the target
    Real distance = 5;                    ///< m from the eye to the target
    Real fieldOfView = Real(0.785398163); ///< rad, vertical (45 degrees)

    Vec3 eye() const;
    /// Unit vectors of the eye's frame: forward (toward the target), right, and up (completing a right-handed frame).
    Vec3 forward() const;
    Vec3 right() const;
    Vec3 up() const;

    /// Clip planes follow the distance, so depth precision stays usable from a close look to the whole room.
    Real nearPlane() const;
    Real farPlane() const;

    /// World to eye (a look-at matrix).
    Mat4 view() const;
    /// Eye to clip, OpenGL conventions (right-handed eye space, depth -1..1).
    Mat4 projection(Real aspect) const;
    Mat4 viewProjection(const Viewport& viewport) const { return projection(viewport.aspect()) * view(); }

    /// Where a world point lands in the window, in pixels from the top-left corner (y down, as mouse events give it);
    /// nothing if the point is behind the eye.
    std::optional<Vec2> project(const Vec3& point, const Viewport& viewport) const;
    /// Width in metres that one pixel spans at the middle of the window, per metre of depth: turns a tolerance in
    /// pixels into a distance from a ray that grows with the depth along it.
    Real pixelSizeAtUnitDepth(const Viewport& viewport) const;

    /// Mouse moves, in pixels. Orbiting keeps the pitch short of straight up or down, where the frame would flip.
    void orbit(Real dxPixels, Real dyPixels);
    /// Moves the target in the view plane so the point under the cursor follows the cursor (at the target's depth).
    void pan(Real dxPixels, Real dyPixels, const Viewport& viewport);
    /// factor < 1 moves closer. The distance stays within a range that keeps the clip planes sane.
    void zoom(Real factor);
};

/// A camera looking at the middle of a box from one of the presets, just far enough back that all of the box fits a
/// window of the given aspect ratio (with a small margin).
OrbitCamera presetCamera(ViewPreset preset, const Vec3& low, const Vec3& high, Real aspect);
} // namespace masse::viewer
