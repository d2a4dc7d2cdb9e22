// The viewer's orbit camera: its frame, projection, mouse moves and preset views.

#include "viewer/Camera.h"

#include "core/InputError.h"

#include <gtest/gtest.h>

#include <cmath>

using namespace masse;
using namespace masse::viewer;

namespace
{
OrbitCamera lookingAtOrigin()
{
    OrbitCamera camera;
    camera.target = Vec3(0.3, -0.5, 0.2);
    camera.yaw = 0.4;
    camera.pitch = 0.3;
    camera.distance = 4;
    return camera;
}
const Viewport window{800, 600};
} // namespace

TEST(Camera, FrameIsOrthonormalRightHandedAndLooksAtTheTarget)
{
    const OrbitCamera camera = lookingAtOrigin();
    EXPECT_NEAR((camera.eye() - camera.target).norm(), camera.distance, 1e-12);
    EXPECT_NEAR((camera.target - camera.eye()).normalized().dot(camera.forward()), 1, 1e-12);
    EXPECT_NEAR(camera.forward().norm(), 1, 1e-12);
    EXPECT_NEAR(camera.right().norm(), 1, 1e-12);
    EXPECT_NEAR(camera.up().norm(), 1, 1e-12);
    EXPECT_NEAR(camera.right().dot(camera.forward()), 0, 1e-12);
    EXPECT_NEAR(camera.up().dot(camera.forward()), 0, 1e-12);
    // Eye space as OpenGL has it: x right, y up, z back toward the viewer.
    EXPECT_NEAR((camera.right().cross(camera.up()) + camera.forward()).norm(), 0, 1e-12);
    EXPECT_GT(camera.up().y(), 0) << "the world's up stays up on screen";
    EXPECT_NEAR(camera.right().y(), 0, 1e-12) << "no roll";
}

TEST(Camera, ViewMatrixTakesTheEyeToTheOriginLookingDownMinusZ)
{
    const OrbitCamera camera = lookingAtOrigin();
    const Mat4 view = camera.view();
    EXPECT_NEAR((view * camera.eye().homogeneous()).head<3>().norm(), 0, 1e-12);
    const Vec3 target = (view * camera.target.homogeneous()).head<3>();
    EXPECT_NEAR(target.x(), 0, 1e-12);
    EXPECT_NEAR(target.y(), 0, 1e-12);
    EXPECT_NEAR(target.z(), -camera.distance, 1e-12);
}

TEST(Camera, ProjectsTheTargetToTheMiddleAndKeepsLeftRightUpDown)
{
    const OrbitCamera camera = lookingAtOrigin();
    const auto middle = camera.project(camera.target, window);
    ASSERT_TRUE(middle);
    EXPECT_NEAR(middle->x(), 400, 1e-9);
    EXPECT_NEAR(middle->y(), 300, 1e-9);
    const auto right = camera.project(camera.target + 0.1 * camera.right(), window);
    const auto above = camera.project(camera.target + 0.1 * camera.up(), window);
    ASSERT_TRUE(right && above);
    EXPECT_GT(right->x(), 400);
    EXPECT_NEAR(right->y(), 300, 1e-9);
    EXPECT_LT(above->y(), 300) << "pixel rows grow downward";
    // The vertical field of view spans the window's height: a point at the top edge of the view lands on row 0.
    const Real halfHeight = camera.distance * std::tan(camera.fieldOfView / 2);
    const auto top = camera.project(camera.target + halfHeight * camera.up(), window);
    ASSERT_TRUE(top);
    EXPECT_NEAR(top->y(), 0, 1e-9);
    EXPECT_FALSE(camera.project(camera.eye() - camera.forward(), window)) << "behind the eye";
}

TEST(Camera, PixelSizeMatchesTheProjection)
{
    const OrbitCamera camera = lookingAtOrigin();
    // One metre right of the target, at the target's depth, is this many pixels right of the middle.
    const auto p = camera.project(camera.target + camera.right(), window);
    ASSERT_TRUE(p);
    EXPECT_NEAR(p->x() - 400, 1 / (camera.distance * camera.pixelSizeAtUnitDepth(window)), 1e-9);
}

TEST(Camera, DraggingUpRaisesTheEyeAndPitchStopsShortOfThePoles)
{
    // The paper (section 7): moving the mouse up goes from the view from below (figure 8) to the view from above.
    OrbitCamera camera = lookingAtOrigin();
    const Real before = camera.eye().y();
    camera.orbit(0, -20);
    EXPECT_GT(camera.eye().y(), before);
    camera.orbit(0, -100000);
    EXPECT_LT(camera.pitch, M_PI / 2);
    EXPECT_GT(camera.up().y(), 0);
    EXPECT_TRUE(camera.right().allFinite());
    camera.orbit(0, 100000);
    EXPECT_GT(camera.pitch, -M_PI / 2);
    EXPECT_TRUE(camera.right().allFinite());
    // Orbiting keeps the target and the distance.
    EXPECT_NEAR((camera.eye() - camera.target).norm(), camera.distance, 1e-12);
}

TEST(Camera, PanMovesTheSceneWithTheCursor)
{
    OrbitCamera camera = lookingAtOrigin();
    const Vec3 point = camera.target;
    camera.pan(30, -20, window);
    const auto p = camera.project(point, window);
    ASSERT_TRUE(p);
    EXPECT_NEAR(p->x(), 400 + 30, 1e-6);
    EXPECT_NEAR(p->y(), 300 - 20, 1e-6);
}

TEST(Camera, ZoomScalesTheDistanceWithinLimits)
{
    OrbitCamera camera = lookingAtOrigin();
    camera.zoom(0.5);
    EXPECT_NEAR(camera.distance, 2, 1e-12);
    camera.zoom(1e-9);
    EXPECT_GT(camera.distance, 0);
    EXPECT_GT(camera.distance, camera.nearPlane());
    camera.zoom(1e12);
    EXPECT_LT(camera.distance, camera.farPlane());
}

TEST(Camera, PresetsFrameTheBoxTightlyFromTheirSide)
{
    // The paper's drop scene: the sheet above a block and a wedge standing on the floor.
    const Vec3 low(-0.85, -2.81, -0.5);
    const Vec3 high(1.45, 0.4, 1.1);
    for (const Viewport& screen : {Viewport{1024, 720}, Viewport{600, 800}})
    {
        for (ViewPreset preset : {ViewPreset::Overview, ViewPreset::FromBelow, ViewPreset::ElevatedLeft})
        {
            const OrbitCamera camera = presetCamera(preset, low, high, screen.aspect());
            EXPECT_NEAR((camera.target - (low + high) / 2).norm(), 0, 1e-12);
            Real closestToAnEdge = 1e9;
            for (int corner = 0; corner < 8; ++corner)
            {
                const Vec3 p((corner & 1) ? high.x() : low.x(), (corner & 2) ? high.y() : low.y(),
                             (corner & 4) ? high.z() : low.z());
                const auto pixel = camera.project(p, screen);
                ASSERT_TRUE(pixel);
                EXPECT_GE(pixel->x(), 0);
                EXPECT_LE(pixel->x(), screen.width);
                EXPECT_GE(pixel->y(), 0);
                EXPECT_LE(pixel->y(), screen.height);
                closestToAnEdge = std::min(
                    {closestToAnEdge, pixel->x(), screen.width - pixel->x(), pixel->y(), screen.height - pixel->y()});
            }
            EXPECT_LT(closestToAnEdge, 0.1 * std::min(screen.width, screen.height)) << "no farther than needed";
        }
    }
    const OrbitCamera below = presetCamera(ViewPreset::FromBelow, low, high, 1.4);
    EXPECT_LT(below.eye().y(), low.y()) << "figure 8: from below";
    const OrbitCamera left = presetCamera(ViewPreset::ElevatedLeft, low, high, 1.4);
    EXPECT_GT(left.eye().y(), high.y()) << "figure 9: elevated";
    EXPECT_LT(left.eye().x(), low.x()) << "figure 9: from the left (-x)";
}

TEST(Camera, ParsesPresetNames)
{
    EXPECT_EQ(parseViewPreset("overview"), ViewPreset::Overview);
    EXPECT_EQ(parseViewPreset("below"), ViewPreset::FromBelow);
    EXPECT_EQ(parseViewPreset("left"), ViewPreset::ElevatedLeft);
    EXPECT_THROW(parseViewPreset("sideways"), InputError);
}
