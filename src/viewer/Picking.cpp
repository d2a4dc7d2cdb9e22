#include "Picking.h"

#include <cmath>
#include <limits>

namespace masse::viewer
{
Ray rayThroughPixel(const OrbitCamera& camera, const Viewport& viewport, Real x, Real y)
{
    // Normalised device coordinates of the pixel, then the eye-space direction through it at unit depth.
    const Real ndcX = Real(2) * x / Real(viewport.width) - 1;
    const Real ndcY = 1 - Real(2) * y / Real(viewport.height);
    const Real halfHeight = std::tan(camera.fieldOfView / 2);
    const Real halfWidth = halfHeight * viewport.aspect();
    const Vec3 direction = camera.forward() + ndcX * halfWidth * camera.right() + ndcY * halfHeight * camera.up();
    return {camera.eye(), direction.normalized()};
}

std::optional<MassPick> pickNearestMass(const std::vector<Vec3>& positions, const Ray& ray, Real pixelSizeAtUnitDepth,
                                        Real tolerancePixels)
{
    // A mass at depth t along the ray and distance d from it appears d / (t * pixelSizeAtUnitDepth) pixels away.
    const Real tolerance = tolerancePixels * pixelSizeAtUnitDepth;
    std::optional<MassPick> best;
    Real bestDepth = std::numeric_limits<Real>::infinity();
    for (std::size_t i = 0; i < positions.size(); ++i)
    {
        const Vec3 offset = positions[i] - ray.origin;
        const Real depth = offset.dot(ray.direction);
        if (depth <= 0 || depth >= bestDepth)
        {
            continue;
        }
        const Real distance = (offset - depth * ray.direction).norm();
        if (distance <= tolerance * depth)
        {
            bestDepth = depth;
            best = MassPick{Index(i), depth, distance / (depth * pixelSizeAtUnitDepth)};
        }
    }
    return best;
}

DragPlane dragPlaneFacing(const OrbitCamera& camera, const Vec3& through)
{
    return {through, -camera.forward()};
}

std::optional<Vec3> intersect(const Ray& ray, const DragPlane& plane)
{
    const Real approach = ray.direction.dot(plane.normal);
    // Within a hair of parallel the meeting point runs off to infinity; keep the previous target instead.
    if (std::abs(approach) < Real(1e-9))
    {
        return std::nullopt;
    }
    const Real t = (plane.point - ray.origin).dot(plane.normal) / approach;
    if (t < 0)
    {
        return std::nullopt;
    }
    return ray.origin + t * ray.direction;
}
} // namespace masse::viewer
