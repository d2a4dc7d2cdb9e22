// The viewer's controls without a window: events in, camera moves and session commands out, carried out on a real
// session as the simulation thread would; and the snapshot the window draws from.

#include "viewer/Controls.h"
#include "viewer/SceneSnapshot.h"
#include "viewer/SimulationThread.h"

#include "scene/SceneFile.h"

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

namespace masse::viewer
{
namespace
{
scene::SceneSpec dropScene()
{
    return scene::loadScene(std::string(MASSE_SOURCE_DIR) + "/data/scenes/paper-drop.json");
}

/// A session, its snapshot, and controls framing it in an 800x600 window; commands are queued, then carried out.
struct Rig
{
    ViewerSession session{dropScene()};
    MassScalarRegistry scalars = standardMassScalars();
    SceneSnapshot snapshot;
    Controls controls{ViewPreset::Overview, DrawSettings{}};
    std::vector<SessionCommand> queued;
    CommandSink post = [this](SessionCommand command) { queued.push_back(std::move(command)); };

    Rig()
    {
        session.setPaused(true);
        captureSnapshot(session, scalars, "", nullptr, snapshot);
        controls.viewport = {800, 600};
        controls.setView(ViewPreset::Overview, snapshot);
    }
    void carryOut()
    {
        for (SessionCommand& command : queued)
        {
            command(session);
        }
        queued.clear();
        captureSnapshot(session, scalars, "", &snapshot, snapshot);
    }
    void key(int slot, Modifiers modifiers = {}, UiCapture ui = {})
    {
        InputEvent event;
        event.kind = InputKind::KeyDown;
        event.key = slot;
        event.modifiers = modifiers;
        controls.handle(event, ui, snapshot, post);
    }
    void mouse(InputKind kind, int x, int y, Modifiers modifiers = {}, UiCapture ui = {})
    {
        InputEvent event;
        event.kind = kind;
        event.x = x;
        event.y = y;
        event.modifiers = modifiers;
        controls.handle(event, ui, snapshot, post);
    }
};
} // namespace

TEST(Controls, SpaceRunsAndPausesThroughTheSessionQueue)
{
    Rig rig;
    ASSERT_TRUE(rig.session.paused());
    rig.key(' ');
    EXPECT_TRUE(rig.session.paused()) << "nothing happens to the session until the command is carried out";
    ASSERT_EQ(rig.queued.size(), 1u);
    rig.carryOut();
    EXPECT_FALSE(rig.session.paused());
    EXPECT_FALSE(rig.snapshot.paused);
}

TEST(Controls, KeysTypedIntoAFieldAreNotTheWindowsAndCtrlLettersNeither)
{
    Rig rig;
    rig.key(' ', {}, UiCapture{false, true});
    rig.key('R', {true, false, false});
    rig.key('Q', {}, UiCapture{false, true});
    EXPECT_TRUE(rig.queued.empty());
    EXPECT_FALSE(rig.controls.quit);
    rig.key('Q');
    EXPECT_TRUE(rig.controls.quit);
}

TEST(Controls, CtrlClickOnAMassPicksItAndTheReleaseLetsGo)
{
    Rig rig;
    const Index mass = rig.snapshot.positions.size() / 2;
    const std::optional<Vec2> pixel = rig.controls.camera.project(rig.snapshot.positions[mass], rig.controls.viewport);
    ASSERT_TRUE(pixel);
    rig.mouse(InputKind::MouseDown, int(pixel->x()), int(pixel->y()), {true, false, false});
    ASSERT_TRUE(rig.controls.pick) << "the window's own pick is there at once, for the next frame to draw";
    // Within the pick tolerance (12 px) of the cursor: the mass under it or a neighbour as close on screen.
    const std::optional<Vec2> picked =
        rig.controls.camera.project(rig.snapshot.positions[rig.controls.pick->first], rig.controls.viewport);
    ASSERT_TRUE(picked);
    EXPECT_LE((*picked - *pixel).norm(), 12.0);
    rig.carryOut();
    ASSERT_TRUE(rig.session.pickedMass());
    EXPECT_EQ(*rig.session.pickedMass(), rig.controls.pick->first);
    EXPECT_EQ(rig.snapshot.pickedMass, rig.session.pickedMass());

    rig.mouse(InputKind::MouseMove, int(pixel->x()), int(pixel->y()) - 40);
    rig.carryOut();
    EXPECT_GT(rig.session.pickTarget()->y(), rig.snapshot.positions[*rig.session.pickedMass()].y())
        << "dragging up moves the spring's target above the mass";

    rig.mouse(InputKind::MouseUp, int(pixel->x()), int(pixel->y()) - 40);
    EXPECT_FALSE(rig.controls.pick);
    rig.carryOut();
    EXPECT_FALSE(rig.session.pickedMass());
}

TEST(Controls, APlainDragOrbitsAndTheWheelOverThePanelDoesNotZoom)
{
    Rig rig;
    const Real yaw = rig.controls.camera.yaw;
    rig.mouse(InputKind::MouseDown, 700, 500);
    rig.mouse(InputKind::MouseMove, 740, 500);
    rig.mouse(InputKind::MouseUp, 740, 500);
    EXPECT_NE(rig.controls.camera.yaw, yaw);
    EXPECT_TRUE(rig.queued.empty());

    const Real distance = rig.controls.camera.distance;
    InputEvent wheel;
    wheel.kind = InputKind::Wheel;
    wheel.wheel = 1;
    rig.controls.handle(wheel, UiCapture{true, false}, rig.snapshot, rig.post);
    EXPECT_EQ(rig.controls.camera.distance, distance);
    rig.controls.handle(wheel, UiCapture{}, rig.snapshot, rig.post);
    EXPECT_LT(rig.controls.camera.distance, distance);
}

TEST(Controls, FollowKeepsTheTargetOnTheFallingSheet)
{
    Rig rig;
    rig.key('F');
    ASSERT_TRUE(rig.controls.follow);
    rig.session.setPaused(false);
    for (int i = 0; i < 20; ++i)
    {
        rig.session.advanceSteps(1);
    }
    rig.carryOut();
    rig.controls.update(rig.snapshot);
    const Vec3 centre = sheetCentre(rig.snapshot.positions);
    EXPECT_LT((rig.controls.camera.target - centre).norm(), 1e-12);
    // The sheet fell: 20 steps of 0.03 s under gravity take it below where it started.
    EXPECT_LT(centre.y(), 0.3);
}

TEST(SceneSnapshot, AScalarTheSceneLacksIsNamedMissingNotPaintedUniform)
{
    ViewerSession session(dropScene());
    SceneSnapshot snapshot;
    captureSnapshot(session, standardMassScalars(), "temperature", nullptr, snapshot);
    EXPECT_TRUE(snapshot.scalar.empty());
    EXPECT_NE(snapshot.scalarMissing.find("no heat"), std::string::npos) << snapshot.scalarMissing;
    captureSnapshot(session, standardMassScalars(), "speed", &snapshot, snapshot);
    EXPECT_TRUE(snapshot.scalarMissing.empty());
    EXPECT_EQ(snapshot.scalar.size(), snapshot.positions.size());
}

// The panel greys out what a scene lacks: the drop scene has neither heat nor material, drape forming has both.
TEST(SceneSnapshot, ListsEveryScalarTheSceneLacksWithItsReason)
{
    const MassScalarRegistry scalars = standardMassScalars();
    ViewerSession drop(dropScene());
    SceneSnapshot snapshot;
    captureSnapshot(drop, scalars, "", nullptr, snapshot);
    EXPECT_NE(missingScalarReason(snapshot, "temperature").find("no heat"), std::string::npos);
    EXPECT_NE(missingScalarReason(snapshot, "thickness").find("no material"), std::string::npos);
    EXPECT_NE(missingScalarReason(snapshot, "thickness_ratio").find("no material"), std::string::npos);
    EXPECT_EQ(missingScalarReason(snapshot, "speed"), "");
    EXPECT_EQ(missingScalarReason(snapshot, "strain"), "");
    EXPECT_EQ(snapshot.missingScalars.size(), 3u);

    ViewerSession drape(scene::loadScene(std::string(MASSE_SOURCE_DIR) + "/data/scenes/drape-forming.json"));
    captureSnapshot(drape, scalars, "thickness_ratio", nullptr, snapshot);
    EXPECT_TRUE(snapshot.missingScalars.empty());
    ASSERT_EQ(snapshot.scalar.size(), snapshot.positions.size());
    EXPECT_NEAR(snapshot.scalar[0], 1.0f, 1e-6f) << "h / h0 is 1 before the sheet stretches";
}

TEST(SimulationThread, CommandsAreCarriedOutAndPublishedWhileTheWindowNeverWaits)
{
    ViewerSession session(dropScene());
    session.setPaused(true);
    const MassScalarRegistry scalars = standardMassScalars();
    SimulationThread simulation(session, scalars, false, 0.02);
    simulation.start();
    const std::shared_ptr<const SceneSnapshot> first = simulation.latest();
    ASSERT_TRUE(first);
    EXPECT_EQ(first->time, 0.0);
    simulation.post([](ViewerSession& s) { s.setPaused(false); });
    const std::uint64_t ticket = simulation.postSteps(5);
    simulation.waitFor(ticket);
    const std::shared_ptr<const SceneSnapshot> later = simulation.latest();
    EXPECT_EQ(later->steps, 5u);
    EXPECT_NEAR(later->time, 5 * 0.03, 1e-12);
    // The snapshot held by the window stays as it was while later ones are published (double buffering).
    EXPECT_EQ(first->time, 0.0);
    simulation.stop();
    EXPECT_NEAR(session.scene().time(), 5 * 0.03, 1e-12);
}

// A scalar chosen while the viewer is paused is painted at once: the thread publishes its values without waiting for
// a step, so the sheet is not left grey ("waiting for values") until the user resumes.
TEST(SimulationThread, AScalarChosenWhilePausedIsPublishedWithoutAStep)
{
    ViewerSession session(dropScene());
    session.setPaused(true);
    const MassScalarRegistry scalars = standardMassScalars();
    SimulationThread simulation(session, scalars, true, 0.02);
    simulation.start();
    ASSERT_TRUE(simulation.latest()->scalar.empty());
    simulation.setScalar("speed");
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
    while (simulation.latest()->scalar.empty() && std::chrono::steady_clock::now() < deadline)
    {
        std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
    const std::shared_ptr<const SceneSnapshot> painted = simulation.latest();
    EXPECT_EQ(painted->scalar.size(), painted->positions.size());
    EXPECT_EQ(painted->steps, 0u) << "paused: no step was taken";
    simulation.stop();
}
} // namespace masse::viewer
