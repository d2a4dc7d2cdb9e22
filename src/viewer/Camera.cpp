#include "Camera.h"

#include "core/InputError.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace masse::viewer
{
namespace
{
constexpr Real degree = Real(0.017453292519943295);
/// Short of +-90 degrees: at the poles forward and the world's up coincide and the right vector is undefined.
constexpr Real maxPitch = 89 * degree;
constexpr Real orbitRadiansPerPixel = Real(0.008);
constexpr Real minDistance = Real(0.05);
constexpr Real maxDistance = Real(200);
} // namespace

ViewPreset parseViewPreset(std::string_view name)
{
    if (name == "overview")
    {
        return ViewPreset::Overview;
    }
    if (name == "below")
    {
        return ViewPreset::FromBelow;
    }
    if (name == "left")
    {
        return ViewPreset::ElevatedLeft;
    }
    throw InputError("view: unknown view '" + std::string(name) + "' (expected overview, below, left)");
}

Vec3 OrbitCamera::eye() const
{
    return target - distance * forward();
}

Vec3 OrbitCamera::forward() const
{
    // The eye sits at target + distance * (cos p sin y, sin p, cos p cos y); forward points back from there.
    return -Vec3(std::cos(pitch) * std::sin(yaw), std::sin(pitch), std::cos(pitch) * std::cos(yaw));
}

Vec3 OrbitCamera::right() const
{
    return forward().cross(Vec3::UnitY()).normalized();
}

Vec3 OrbitCamera::up() const
{
    return right().cross(forward());
}

Real OrbitCamera::nearPlane() const
{
    return std::max(Real(0.005), Real(0.01) * distance);
}

Real OrbitCamera::farPlane() const
{
    // Far enough to see across the paper's room (13 m wide) from anywhere near it.
    return Real(4) * distance + Real(50);
}

Mat4 OrbitCamera::view() const
{
    const Vec3 f = forward();
    const Vec3 r = right();
    const Vec3 u = up();
    const Vec3 e = eye();
    Mat4 m = Mat4::Identity();
    m.block<1, 3>(0, 0) = r.transpose();
    m.block<1, 3>(1, 0) = u.transpose();
    m.block<1, 3>(2, 0) = -f.transpose();
    m(0, 3) = -r.dot(e);
    m(1, 3) = -u.dot(e);
    m(2, 3) = f.dot(e);
    return m;
}

Mat4 OrbitCamera::projection(Real aspect) const
{
    const Real f = Real(1) / std::tan(fieldOfView / 2);
    const Real n = nearPlane();
    const Real fa = farPlane();
    Mat4 m = Mat4::Zero();
    m(0, 0) = f / aspect;
    m(1, 1) = f;
    m(2, 2) = (fa + n) / (n - fa);
    m(2, 3) = Real(2) * fa * n / (n - fa);
    m(3, 2) = -1;
    return m;
}

std::optional<Vec2> OrbitCamera::project(const Vec3& point, const Viewport& viewport) const
{
    const Eigen::Matrix<Real, 4, 1> clip = viewProjection(viewport) * point.homogeneous();
    if (clip.w() <= 0)
    {
        return std::nullopt;
    }
    const Real x = clip.x() / clip.w();
    const Real y = clip.y() / clip.w();
    return Vec2((x + 1) / 2 * viewport.width, (1 - y) / 2 * viewport.height);
}

Real OrbitCamera::pixelSizeAtUnitDepth(const Viewport& viewport) const
{
    return Real(2) * std::tan(fieldOfView / 2) / Real(std::max(1, viewport.height));
}

void OrbitCamera::orbit(Real dxPixels, Real dyPixels)
{
    // Dragging right swings the eye left round the target, so the scene turns with the mouse; dragging up raises
    // the eye (the paper's move from figure 8, below the sheet, to figure 9, above it).
    yaw -= dxPixels * orbitRadiansPerPixel;
    pitch = std::clamp(pitch - dyPixels * orbitRadiansPerPixel, -maxPitch, maxPitch);
}

void OrbitCamera::pan(Real dxPixels, Real dyPixels, const Viewport& viewport)
{
    const Real metresPerPixel = distance * pixelSizeAtUnitDepth(viewport);
    target += metresPerPixel * (-dxPixels * right() + dyPixels * up());
}

void OrbitCamera::zoom(Real factor)
{
    distance = std::clamp(distance * factor, minDistance, maxDistance);
}

OrbitCamera presetCamera(ViewPreset preset, const Vec3& low, const Vec3& high, Real aspect)
{
    OrbitCamera camera;
    camera.target = (low + high) / 2;
    switch (preset)
    {
    case ViewPreset::Overview:
        camera.yaw = -35 * degree;
        camera.pitch = 25 * degree;
        break;
    case ViewPreset::FromBelow:
        camera.yaw = -20 * degree;
        camera.pitch = -50 * degree;
        break;
    case ViewPreset::ElevatedLeft:
        camera.yaw = -90 * degree;
        camera.pitch = 35 * degree;
        break;
    }
    // Each corner, in the eye's frame, needs the eye at least so far back that it falls inside both fields of view.
    constexpr Real margin = Real(1.08);
    const Real tanHalfHeight = std::tan(camera.fieldOfView / 2);
    const Real tanHalfWidth = tanHalfHeight * aspect;
    const Vec3 towardEye = -camera.forward();
    Real distance = minDistance;
    for (int corner = 0; corner < 8; ++corner)
    {
        const Vec3 p((corner & 1) ? high.x() : low.x(), (corner & 2) ? high.y() : low.y(),
                     (corner & 4) ? high.z() : low.z());
        const Vec3 offset = p - camera.target;
        const Real nearer = offset.dot(towardEye);
        distance = std::max(distance, nearer + margin * std::abs(offset.dot(camera.up())) / tanHalfHeight);
        distance = std::max(distance, nearer + margin * std::abs(offset.dot(camera.right())) / tanHalfWidth);
    }
    camera.distance = std::min(distance, maxDistance);
    return camera;
}
} // namespace masse::viewer
