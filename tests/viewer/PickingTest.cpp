// Mouse picking (paper section 7): rays through pixels, the nearest mass under the cursor, the drag plane.

#include "viewer/Picking.h"

#include <gtest/gtest.h>

using namespace masse;
using namespace masse::viewer;

namespace
{
OrbitCamera testCamera()
{
    OrbitCamera camera;
    camera.target = Vec3(0.3, 0.35, 0.3);
    camera.yaw = -0.6;
    camera.pitch = 0.45;
    camera.distance = 3;
    return camera;
}
const Viewport window{1024, 720};

Real distanceFromRay(const Ray& ray, const Vec3& p)
{
    const Vec3 offset = p - ray.origin;
    return (offset - offset.dot(ray.direction) * ray.direction).norm();
}
} // namespace

TEST(Picking, RayThroughTheMiddleIsTheViewDirection)
{
    const OrbitCamera camera = testCamera();
    const Ray ray = rayThroughPixel(camera, window, 512, 360);
    EXPECT_NEAR((ray.origin - camera.eye()).norm(), 0, 1e-12);
    EXPECT_NEAR(ray.direction.dot(camera.forward()), 1, 1e-12);
    EXPECT_NEAR(ray.direction.norm(), 1, 1e-12);
}

TEST(Picking, RayThroughAPointsPixelPassesThroughThePoint)
{
    const OrbitCamera camera = testCamera();
    for (const Vec3& point : {Vec3(-0.2, 0.3, -0.2), Vec3(0.8, 0.4, 0.8), Vec3(1.1, -0.6, 0.1)})
    {
        const auto pixel = camera.project(point, window);
        ASSERT_TRUE(pixel);
        const Ray ray = rayThroughPixel(camera, window, pixel->x(), pixel->y());
        EXPECT_LT(distanceFromRay(ray, point), 1e-9) << point.transpose();
    }
}

TEST(Picking, PicksTheMassNearestTheEyeAmongThoseUnderTheCursor)
{
    const OrbitCamera camera = testCamera();
    const Ray ray = rayThroughPixel(camera, window, 600, 300);
    const Real size = camera.pixelSizeAtUnitDepth(window);
    // Two masses on the ray (the sheet's two layers), one beside it, one behind the eye.
    const Vec3 side = ray.direction.cross(Vec3::UnitY()).normalized();
    const std::vector<Vec3> masses{
        ray.origin + 3.2 * ray.direction,                          // farther, exactly under the cursor
        ray.origin + 3.0 * ray.direction + 5 * size * 3.0 * side,  // nearer, 5 pixels off
        ray.origin + 2.0 * ray.direction + 40 * size * 2.0 * side, // nearest, but 40 pixels off
        ray.origin - 1.0 * ray.direction,                          // behind the eye
    };
    const std::optional<MassPick> pick = pickNearestMass(masses, ray, size, 12);
    ASSERT_TRUE(pick);
    EXPECT_EQ(pick->mass, 1u);
    EXPECT_NEAR(pick->depth, 3.0, 1e-9);
    EXPECT_NEAR(pick->pixelOffset, 5, 1e-6);

    EXPECT_EQ(pickNearestMass(masses, ray, size, 3)->mass, 0u) << "with a tighter tolerance only the one on the ray";
    EXPECT_FALSE(pickNearestMass({masses[2], masses[3]}, ray, size, 12)) << "nothing under the cursor";
    EXPECT_FALSE(pickNearestMass({}, ray, size, 12));
}

TEST(Picking, ToleranceIsInPixelsAtAnyDepth)
{
    const OrbitCamera camera = testCamera();
    const Ray ray = rayThroughPixel(camera, window, 512, 360);
    const Real size = camera.pixelSizeAtUnitDepth(window);
    const Vec3 side = camera.right();
    for (Real depth : {0.5, 3.0, 20.0})
    {
        const std::vector<Vec3> inside{ray.origin + depth * ray.direction + 9 * size * depth * side};
        const std::vector<Vec3> outside{ray.origin + depth * ray.direction + 15 * size * depth * side};
        EXPECT_TRUE(pickNearestMass(inside, ray, size, 12)) << depth;
        EXPECT_FALSE(pickNearestMass(outside, ray, size, 12)) << depth;
    }
}

TEST(Picking, DragPlaneFacesTheCameraThroughThePickedMass)
{
    const OrbitCamera camera = testCamera();
    const Vec3 mass(0.5, 0.3, 0.1);
    const DragPlane plane = dragPlaneFacing(camera, mass);
    EXPECT_NEAR(plane.normal.dot(-camera.forward()), 1, 1e-12);

    // The cursor over the mass puts the target on the mass; moving it keeps the target at the mass's depth.
    const auto pixel = camera.project(mass, window);
    ASSERT_TRUE(pixel);
    const auto onMass = intersect(rayThroughPixel(camera, window, pixel->x(), pixel->y()), plane);
    ASSERT_TRUE(onMass);
    EXPECT_LT((*onMass - mass).norm(), 1e-9);
    const auto moved = intersect(rayThroughPixel(camera, window, pixel->x() + 50, pixel->y() - 80), plane);
    ASSERT_TRUE(moved);
    EXPECT_NEAR((*moved - mass).dot(plane.normal), 0, 1e-9);
    const auto back = camera.project(*moved, window);
    ASSERT_TRUE(back);
    EXPECT_NEAR(back->x(), pixel->x() + 50, 1e-6);
    EXPECT_NEAR(back->y(), pixel->y() - 80, 1e-6);
}

TEST(Picking, RayParallelToOrAwayFromThePlaneMissesIt)
{
    const DragPlane plane{Vec3::Zero(), Vec3::UnitY()};
    EXPECT_FALSE(intersect(Ray{Vec3(0, 1, 0), Vec3::UnitX()}, plane));
    EXPECT_FALSE(intersect(Ray{Vec3(0, 1, 0), Vec3::UnitY()}, plane));
    const auto hit = intersect(Ray{Vec3(0, 1, 0), -Vec3::UnitY()}, plane);
    ASSERT_TRUE(hit);
    EXPECT_NEAR(hit->norm(), 0, 1e-12);
}
