// The forming bench without a window: the process controls turn the panel's and the keys' requests into script
// actions at the scene's time; the session saves the run as a scene file that replays to the same state; a scene
// edited in the panel cannot be saved; a mouse pull is flagged; the thickness colours span 0 to h0 and the thinnest
// point is in the snapshot.

#include "viewer/ProcessControls.h"
#include "viewer/Controls.h"
#include "viewer/MassScalars.h"
#include "viewer/SceneGeometry.h"
#include "viewer/SceneSnapshot.h"
#include "viewer/ViewerSession.h"

#include "core/StateHash.h"
#include "scene/SceneFile.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace masse;
using namespace masse::viewer;

namespace
{
const std::string plugCup = std::string(MASSE_SOURCE_DIR) + "/data/scenes/plug-assist-cup.json";

scene::RunSource plugCupAt(const std::string& size)
{
    scene::RunSource source;
    source.path = plugCup;
    source.flags.size = size;
    source.flags.dt = "0.01"; // ten steps a tenth of a second
    return source;
}

/// A session on the plug-assist cup at 12x2x12, as `masse view --size 12x2x12 --dt 0.01` starts it.
struct Bench
{
    Bench() : session(scene::loadScene(plugCup, plugCupAt("12x2x12").flags))
    {
        session.setSource(plugCupAt("12x2x12"));
        capture();
    }
    void capture() { captureSnapshot(session, standardMassScalars(), "thickness_ratio", nullptr, snapshot); }
    /// Carries out what the controls post, as the simulation thread does between steps.
    CommandSink sink()
    {
        return [this](SessionCommand command) { command(session); };
    }
    void steps(int n)
    {
        session.advanceSteps(n);
        capture();
    }

    ViewerSession session;
    SceneSnapshot snapshot;
    ProcessControls process;
};

std::string temporaryPath(const std::string& name)
{
    return (std::filesystem::temp_directory_path() / name).string();
}
} // namespace

// Each request is an action at the scene's time, which acts from the next frame: the plug nudged down twice while it
// moves goes two steps down from where the first nudge found it; the vacuum switched on goes to the level over the
// ramp, and off again.
TEST(ProcessControls, RequestsBecomeActionsAtTheScenesTime)
{
    Bench bench;
    bench.process.update(bench.snapshot);
    EXPECT_EQ(bench.process.level, 80000) << "the scene's own level";
    bench.steps(10);
    const std::optional<std::size_t> plug = ProcessControls::steeredObstacle(bench.snapshot);
    ASSERT_TRUE(plug);
    EXPECT_EQ(bench.snapshot.obstacles[*plug].name, "plug");
    const Real startY = bench.snapshot.obstacles[*plug].position.y();
    bench.process.step = 0.01;
    bench.process.speed = 0.05;
    bench.process.nudge(bench.snapshot, -1, bench.sink());
    bench.process.nudge(bench.snapshot, -1, bench.sink()); // the plug is moving (its own path): the nudges add up
    bench.process.ramp = 0.1;
    bench.process.switchPressure(bench.snapshot, bench.sink());
    const std::vector<scene::ScriptAction>& added = bench.session.scene().addedActions();
    ASSERT_EQ(added.size(), 3u);
    for (const scene::ScriptAction& a : added)
    {
        EXPECT_EQ(a.time, bench.session.scene().time());
    }
    EXPECT_NEAR(added[1].target.y(), startY - 0.02, 1e-12);
    EXPECT_EQ(added[2].kind, scene::ScriptAction::Kind::Pressure);
    EXPECT_EQ(added[2].pressure, 80000);
    bench.steps(10); // 0.1 s
    EXPECT_NEAR(bench.snapshot.process.pressure, 80000, 1e-6);
    EXPECT_NEAR(bench.snapshot.obstacles[*plug].position.y(), startY - 0.005, 1e-9) << "0.1 s at 50 mm/s";
    bench.process.switchPressure(bench.snapshot, bench.sink());
    bench.steps(10);
    EXPECT_EQ(bench.snapshot.process.pressure, 0);
    EXPECT_EQ(bench.snapshot.process.recordedActions, 4u);
}

// "Save run" writes a scene file that masse run's reader takes, holding the actions after the scene's own script,
// which replays to the state the session saved at.
TEST(ProcessControls, ASavedRunReplaysToTheSavedState)
{
    Bench bench;
    bench.steps(20);
    bench.process.nudge(bench.snapshot, -1, bench.sink());
    bench.process.switchPressure(bench.snapshot, bench.sink());
    bench.steps(15);
    bench.process.setObstacleTemperature("mould", 90, bench.sink());
    bench.steps(5);
    const std::string path = temporaryPath("masse-bench-saved.run.json");
    std::filesystem::remove(path);
    bench.process.saveRunPath = path;
    bench.process.saveRun(bench.snapshot, bench.sink());
    EXPECT_EQ(bench.session.error(), "");
    EXPECT_NE(bench.session.notice().find("3 action(s)"), std::string::npos) << bench.session.notice();
    const std::uint64_t live = stateHash(bench.session.scene().system().particles);

    scene::Scene replay(scene::loadScene(path));
    EXPECT_EQ(replay.spec().script.size(), 3u);
    while (!replay.finished())
    {
        replay.step();
    }
    EXPECT_EQ(replay.time(), bench.session.scene().time());
    EXPECT_EQ(stateHash(replay.system().particles), live);
    std::filesystem::remove(path);
}

// Nothing on disk describes a scene edited in the panel: saving it is refused, with the reason, and writes nothing.
// A scene loaded from a file can be saved again; a mouse pull is flagged, since the replay will not have it.
TEST(ProcessControls, AnEditedSceneIsNotSavedAndAMousePullIsFlagged)
{
    Bench bench;
    const std::string path = temporaryPath("masse-bench-edited.run.json");
    std::filesystem::remove(path);
    scene::SceneSpec edited = bench.session.spec();
    edited.time.dt = 0.005;
    ASSERT_TRUE(bench.session.rebuild(edited));
    bench.capture();
    EXPECT_FALSE(bench.snapshot.process.saveable);
    EXPECT_FALSE(bench.session.saveRun(path));
    EXPECT_NE(bench.session.error().find("changed in the panel"), std::string::npos) << bench.session.error();
    EXPECT_FALSE(std::filesystem::exists(path));

    ASSERT_TRUE(bench.session.load(plugCup));
    bench.session.beginPick(5, Vec3(0, 0.1, 0));
    bench.steps(2);
    EXPECT_TRUE(bench.snapshot.process.mousePulled);
    EXPECT_TRUE(bench.session.saveRun(path));
    EXPECT_NE(bench.session.notice().find("the mouse's pulls are not in it"), std::string::npos);
    std::filesystem::remove(path);
}

// Thickness is coloured over 0 to h0 (mm) and its ratio over 0 to 1, whatever the values drawn; the thinnest mass
// and its thickness come with every snapshot of a material scene.
TEST(ProcessControls, ThicknessColoursSpanZeroToTheStartingThickness)
{
    Bench bench;
    bench.steps(30);
    ASSERT_TRUE(bench.snapshot.scalarFixedRange);
    EXPECT_EQ(bench.snapshot.scalarFixedRange->low, 0.0f);
    EXPECT_EQ(bench.snapshot.scalarFixedRange->high, 1.0f);
    SceneSnapshot millimetres;
    captureSnapshot(bench.session, standardMassScalars(), "thickness", nullptr, millimetres);
    ASSERT_TRUE(millimetres.scalarFixedRange);
    EXPECT_FLOAT_EQ(millimetres.scalarFixedRange->high, 2.0f) << "h0 = 2 mm";
    ASSERT_TRUE(bench.snapshot.thinnest);
    const SheetThickness& thickness = *bench.session.scene().thickness();
    EXPECT_EQ(bench.snapshot.thinnest->second, thickness.minimumThickness());
    EXPECT_EQ(thickness.thickness()[bench.snapshot.thinnest->first], thickness.minimumThickness());
    SceneSnapshot speed;
    captureSnapshot(bench.session, standardMassScalars(), "speed", nullptr, speed);
    EXPECT_FALSE(speed.scalarFixedRange) << "speed spans its own values";
}

// The live section: set on the session, every snapshot carries the bottom-layer masses along the line (the report's
// thickness_section for the same line, bit for bit), and the overlays draw it; off again, none.
TEST(ProcessControls, TheLiveSectionFollowsTheLineTheUserSets)
{
    Bench bench;
    bench.steps(40);
    scene::SectionSettings line;
    line.axis = 2;
    line.through = Vec3(0.01, 0, 0);
    bench.session.setSection(line);
    bench.capture();
    const std::vector<scene::SectionPoint> expected = scene::thicknessSection(bench.session.scene(), line);
    ASSERT_EQ(bench.snapshot.section.size(), expected.size());
    ASSERT_GT(expected.size(), 5u);
    for (std::size_t k = 0; k < expected.size(); ++k)
    {
        EXPECT_EQ(bench.snapshot.section[k].mass, expected[k].mass);
        EXPECT_EQ(bench.snapshot.section[k].ratio, expected[k].ratio);
        EXPECT_LE(std::abs(bench.session.scene().lattice().position[expected[k].mass].x() - 0.01),
                  0.5 * bench.session.scene().lattice().spacingX + 1e-12)
            << "a mass of the column through x = 0.01 m";
    }
    const std::size_t withSection = buildOverlays(bench.snapshot, std::nullopt).lines.size();
    bench.session.setSection(std::nullopt);
    bench.capture();
    EXPECT_TRUE(bench.snapshot.section.empty());
    EXPECT_EQ(buildOverlays(bench.snapshot, std::nullopt).lines.size() + 2 * (2 * expected.size() - 1), withSection)
        << "a segment between neighbours and a tick at each mass, two vertices a segment";
}

// Alt + left drag moves the plug after the cursor: dragging up the screen sends it up, with a steer only when the
// target has moved a millimetre, and the keys j and k nudge it as the panel's buttons do.
TEST(ProcessControls, TheMouseAndTheKeysSteerThePlug)
{
    Bench bench;
    bench.steps(10);
    Controls controls{ViewPreset::Overview, DrawSettings{}};
    controls.viewport = {800, 600};
    controls.setView(ViewPreset::Overview, bench.snapshot);
    const auto mouse = [&](InputKind kind, int x, int y)
    {
        InputEvent event;
        event.kind = kind;
        event.button = 0;
        event.x = x;
        event.y = y;
        event.modifiers.alt = true;
        controls.handle(event, UiCapture{}, bench.snapshot, bench.sink());
    };
    mouse(InputKind::MouseDown, 400, 300);
    mouse(InputKind::MouseMove, 400, 300); // no move: no steer
    EXPECT_TRUE(bench.session.scene().addedActions().empty());
    mouse(InputKind::MouseMove, 400, 250);
    mouse(InputKind::MouseMove, 400, 200);
    mouse(InputKind::MouseUp, 400, 200);
    const std::vector<scene::ScriptAction>& added = bench.session.scene().addedActions();
    ASSERT_EQ(added.size(), 2u);
    const Real startY = bench.snapshot.obstacles[*ProcessControls::steeredObstacle(bench.snapshot)].position.y();
    EXPECT_EQ(added[0].kind, scene::ScriptAction::Kind::Steer);
    EXPECT_GT(added[0].target.y(), startY + 0.001) << "up the screen is up";
    EXPECT_GT(added[1].target.y(), added[0].target.y());

    InputEvent key;
    key.kind = InputKind::KeyDown;
    key.key = 'j';
    controls.handle(key, UiCapture{}, bench.snapshot, bench.sink());
    ASSERT_EQ(added.size(), 3u);
    EXPECT_EQ(added[2].obstacle, "plug");
}
