// The scene runtime: scripted actions, kinematic obstacles, rest detection, and the paper's drop experiment.

#include "scene/Scene.h"
#include "scene/PaperExperiment.h"
#include "scene/Runner.h"
#include "scene/SceneFile.h"
#include "support/TestSystems.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>

using namespace masse;
using namespace masse::scene;

namespace
{
const std::string source = MASSE_SOURCE_DIR;

SceneSpec sceneFrom(const std::string& json)
{
    return parseScene(nlohmann::json::parse(json), source + "/data/scenes", "inline");
}

void runUntil(Scene& scene, Real time)
{
    while (scene.time() < time - 1e-9)
    {
        scene.step();
    }
}
} // namespace

// The paper's experiment (section 9): for every Table 2 size the sheet touches the first polyhedron, then the
// second, then the floor between them, then comes to rest.
TEST(Scene, PaperDropStagesComeInOrderForAllTable2Sizes)
{
    const SceneSpec base = loadScene(source + "/data/scenes/paper-drop.json");
    const std::vector<PaperRow> rows = runPaperExperiment(base, paperSizes);
    ASSERT_EQ(rows.size(), 5u);
    const std::size_t masses[] = {13, 61, 113, 145, 265};
    const std::size_t springs[] = {33, 216, 428, 561, 1068};
    for (std::size_t k = 0; k < rows.size(); ++k)
    {
        EXPECT_TRUE(rows[k].inOrder) << rows[k].size << "x2x" << rows[k].size;
        EXPECT_EQ(rows[k].masses, masses[k]);
        EXPECT_EQ(rows[k].springs, springs[k]);
        for (std::size_t stage = 0; stage < 4; ++stage)
        {
            EXPECT_GE(rows[k].simTime[stage], 0.0) << paperStages[stage];
        }
        // The first contact comes after a free fall of 0.3 - (-0.8) - radius = 1.09 m: sqrt(2 h / g) = 0.471 s,
        // slowed a little by the air (3% per 0.03 s): it must come between that and 10% later.
        EXPECT_GT(rows[k].simTime[0], 0.471);
        EXPECT_LT(rows[k].simTime[0], 0.471 * 1.1);
    }
}

// A scripted grab drags its mass along the path (within what its capped spring allows), and release frees it.
TEST(Scene, ScriptedGrabDragsTheMassAndReleaseLetsGo)
{
    Scene scene(loadScene(source + "/data/scenes/drag.json"));
    runUntil(scene, 2.3);
    const Index held = scene.script().activeGrabs().at(0).first;
    // At 2.3 s the target is at (0.9, 0.01, 0.5); the corner hangs below it on a 20 N/m spring capped at 2 N.
    const Vec3 corner = scene.system().particles.position[held];
    EXPECT_NEAR(corner.x(), 0.9, 0.1);
    EXPECT_GT(corner.y(), -0.2);
    EXPECT_EQ(scene.system().userSprings.size(), 1u);
    runUntil(scene, 3.1);
    EXPECT_EQ(scene.system().userSprings.size(), 0u);
    EXPECT_TRUE(scene.script().activeGrabs().empty());
    EXPECT_NEAR(scene.eventTime("release", "hand"), 3.0, 1e-9);
}

TEST(Scene, PinUnpinAndGravityActions)
{
    Scene scene(sceneFrom(R"({
        "sheet": { "size": "4x2x4", "pinned": { "corners": [0, 1, 2, 3] } },
        "environment": { "room": { "enabled": false } },
        "script": [ { "time": 0.5, "action": "unpin", "masses": { "corners": [2, 3] } },
                    { "time": 1.0, "action": "gravity", "value": [0, 0, 0] } ],
        "run": { "duration": 2, "stop_at_rest": false } })"));
    const std::vector<Index> corners = scene.lattice().bottomCorners();
    const Vec3 start = scene.system().particles.position[corners[2]];
    runUntil(scene, 0.45);
    EXPECT_EQ(scene.system().particles.position[corners[2]], start); // pinned
    runUntil(scene, 0.9);
    EXPECT_LT(scene.system().particles.position[corners[2]].y(), start.y() - 0.01); // free, swinging down
    EXPECT_EQ(scene.system().particles.position[corners[0]],
              scene.lattice().position[corners[0]]); // still pinned
    runUntil(scene, 1.05);
    EXPECT_EQ(scene.system().forces.gravity, Vec3::Zero());
    for (const char* name : {"unpin", "gravity"})
    {
        EXPECT_GE(scene.eventTime(name, name == std::string("unpin") ? "2 masses" : "sheet"), 0.0) << name;
    }
}

// A kinematic plate rising along its path lifts the sheet resting on it, and the sheet never sinks into it.
TEST(Scene, KinematicObstacleLiftsTheSheet)
{
    Scene scene(sceneFrom(R"({
        "sheet": { "size": "6x2x6", "min": [-0.5, 0.01, -0.5], "max": [0.5, 0.11, 0.5] },
        "environment": { "room": { "enabled": false } },
        "obstacles": [ { "name": "plate", "type": "box", "half_extents": [1, 0.5, 1],
                         "path": [ { "time": 0.5, "position": [0, -0.5, 0] },
                                   { "time": 1.5, "position": [0, 0.5, 0] } ] } ],
        "integrator": { "type": "implicit", "dt": 0.03 },
        "run": { "duration": 2, "stop_at_rest": false } })"));
    Real deepest = 0;
    while (scene.time() < 2.0 - 1e-9)
    {
        scene.step();
        const Real top = std::clamp(-0.5 + (scene.time() - 0.5), -0.5, 0.5) + 0.5;
        for (Index i = scene.lattice().layerStart[0]; i < scene.lattice().layerStart[1]; ++i)
        {
            deepest = std::max(deepest, top + scene.spec().contact.radius - scene.system().particles.position[i].y());
        }
    }
    // Lifted by 1 m with the plate (its top ends at y = 1), within 1% of a spacing.
    const Real spacing = scene.lattice().spacingX;
    EXPECT_LT(deepest, 0.01 * spacing + 1e-9);
    EXPECT_NEAR(scene.system().particles.position[0].y(), 1.0 + scene.spec().contact.radius, 0.01 * spacing);
}

// A sheet lying on a table comes to rest long before its script is done: the run waits for the actions still to come
// (a gravity change at 2 s, a grab at 2.5 s released at 3 s) and only then may rest end it.
TEST(Scene, StopAtRestWaitsForPendingScriptActions)
{
    Scene scene(sceneFrom(R"({
        "sheet": { "size": "4x2x4", "min": [-0.2, 0.011, -0.2], "max": [0.2, 0.06, 0.2] },
        "environment": { "room": { "enabled": false } },
        "obstacles": [ { "name": "table", "type": "box", "position": [0, -0.5, 0], "half_extents": [1, 0.5, 1] } ],
        "integrator": { "type": "implicit", "dt": 0.03 },
        "script": [ { "time": 2.0, "action": "gravity", "value": [0, -9.80665, 0] },
                    { "time": 2.5, "action": "grab", "label": "hand", "mass": 0,
                      "path": [ { "position": [-0.2, 0.1, -0.2] } ] },
                    { "time": 3.0, "action": "release", "grab": "hand" } ],
        "run": { "duration": 10, "stop_at_rest": true } })"));
    while (!scene.finished())
    {
        scene.step();
    }
    EXPECT_NEAR(scene.eventTime("gravity", "sheet"), 2.0, 0.03);
    EXPECT_NEAR(scene.eventTime("release", "hand"), 3.0, 0.03);
    EXPECT_GE(scene.eventTime("rest", "sheet"), 3.0);
    EXPECT_LT(scene.time(), 10.0 - 1e-9); // and it did stop at rest
    EXPECT_TRUE(scene.pendingActions().empty());
}

// Script actions at a frame's start run before that frame's stability estimate and contact detection (StepHook's
// beforeFrame). A grab on a spring 100 times stiffer than the sheet's (1e5 N/m on a 1 g mass: omega = 1e4 rad/s)
// fires at 0.06 s; the frame that starts then must already take the substeps the grab needs (h omega < 2, so more
// than 150 for 0.03 s), not the sheet's own (about 28), which would drive the grabbed mass unstably for a frame. The
// frames after it are checked the same way, and the frame before has the sheet's own count.
TEST(Scene, ActionsAtAFramesStartAreInThatFramesStabilityEstimate)
{
    Scene scene(sceneFrom(R"({
        "sheet": { "size": "6x2x6", "min": [-0.2, 0.3, -0.2], "max": [0.2, 0.31, 0.2] },
        "environment": { "room": { "enabled": false } },
        "integrator": { "type": "symplectic", "dt": 0.03 },
        "script": [ { "time": 0.06, "action": "grab", "label": "hand", "mass": 0, "stiffness": 1e5,
                      "path": [ { "position": [-0.2, 0.3, -0.2] } ] } ],
        "run": { "duration": 0.3 } })"));
    const int sheetOnly = scene.simulator().substepsFor(0.03);
    EXPECT_LT(sheetOnly, 60);
    EXPECT_EQ(scene.step().substeps, sheetOnly); // 0 to 0.03
    EXPECT_EQ(scene.step().substeps, sheetOnly); // 0.03 to 0.06
    const StepReport grabbed = scene.step();     // 0.06 to 0.09: the grab fires at its start
    ASSERT_EQ(scene.system().userSprings.size(), 1u);
    EXPECT_EQ(grabbed.substeps, scene.simulator().substepsFor(0.03));
    EXPECT_GT(grabbed.substeps, 150);
}

// A grab stiff enough that the step would need more substeps than the integrator takes (1e6 N/m on a 1e-5 kg mass at
// dt = 1 s: h omega < 2 needs h < 6.3e-6 s, over 150,000 substeps) is refused when it fires, naming the script action
// that made it (its place in the file and its label), not only the step.
TEST(Scene, AGrabTooStiffForTheStepIsNamedAsTheCause)
{
    Scene scene(sceneFrom(R"({
        "sheet": { "size": "4x2x4", "min": [-0.2, 0.3, -0.2], "max": [0.2, 0.31, 0.2], "mass": 1e-5 },
        "environment": { "room": { "enabled": false } },
        "integrator": { "type": "symplectic", "dt": 1 },
        "script": [ { "time": 0, "action": "grab", "label": "hand", "mass": 0, "stiffness": 1e6,
                      "path": [ { "position": [-0.2, 0.3, -0.2] } ] } ],
        "run": { "duration": 2 } })"));
    const std::string message = masse::test::inputErrorOf([&] { scene.step(); });
    EXPECT_EQ(message.rfind("inline: script[0].stiffness: the grab 'hand' of 1e+06 N/m, firing at t = 0 s, makes the "
                            "step too stiff: the symplectic integrator needs ",
                            0),
              0u)
        << message;
    EXPECT_NE(message.find("over the limit of 100000"), std::string::npos) << message;

    // The same grab added while running (the Python module's act, the viewer) has no place in the file: it is named
    // as such.
    Scene running(sceneFrom(R"({
        "sheet": { "size": "4x2x4", "min": [-0.2, 0.3, -0.2], "max": [0.2, 0.31, 0.2], "mass": 1e-5 },
        "environment": { "room": { "enabled": false } },
        "integrator": { "type": "symplectic", "dt": 1 },
        "run": { "duration": 2 } })"));
    running.addAction(readScriptAction(nlohmann::json::parse(R"({ "time": 0, "action": "grab", "label": "hand",
        "mass": 0, "stiffness": 1e6, "path": [ { "position": [-0.2, 0.3, -0.2] } ] })"),
                                       "action"));
    const std::string added = masse::test::inputErrorOf([&] { running.step(); });
    EXPECT_EQ(added.rfind("inline: the grab 'hand' of 1e+06 N/m added while running, firing at t = 0 s, makes the "
                          "step too stiff: the symplectic integrator needs ",
                          0),
              0u)
        << added;
}

// A sheet laid with its bottom layer exactly on an obstacle's top face (the box-landing sheet on a box whose top is
// at y = -0.5) stays where it was placed, as a box and as the same box read from a mesh file, on an explicit and an
// implicit integrator: no mass is pushed out by the contact radius at the first step (which launched the sheet at
// 1.5 m/s and tripped the implicit runs' energy guard), none sinks into the mesh, and the run goes on. Gravity alone
// gives the top layer at most g dt = 0.29 m/s in a frame as it settles on the layer springs: 0.5 m/s is the bound.
TEST(Scene, ASheetStartingOnAnObstaclesTopStaysWherePlaced)
{
    const std::filesystem::path mesh = std::filesystem::path(testing::TempDir()) / "masse-start-on-box.obj";
    std::ofstream(mesh) << "v -0.7 -1.5 -0.7\nv 1.3 -1.5 -0.7\nv 1.3 -1.5 1.3\nv -0.7 -1.5 1.3\n"
                           "v -0.7 -0.5 -0.7\nv 1.3 -0.5 -0.7\nv 1.3 -0.5 1.3\nv -0.7 -0.5 1.3\n"
                           "f 1 2 3\nf 1 3 4\nf 5 8 7\nf 5 7 6\nf 1 5 6\nf 1 6 2\n"
                           "f 2 6 7\nf 2 7 3\nf 3 7 8\nf 3 8 4\nf 4 8 5\nf 4 5 1\n";
    const std::string box =
        R"({ "name": "box", "type": "box", "position": [0.3, -1.0, 0.3], "half_extents": [1, 0.5, 1] })";
    const std::string fromFile = R"({ "name": "box", "type": "mesh", "file": ")" + mesh.string() + R"(" })";
    for (const std::string& obstacle : {box, fromFile})
    {
        for (const std::string integrator : {"symplectic", "implicit"})
        {
            SCOPED_TRACE(obstacle + " " + integrator);
            Scene scene(sceneFrom(R"({
                "sheet": { "structure": "trimm", "size": "8x2x8", "min": [-0.2, -0.5, -0.2], "max": [0.8, -0.4, 0.8],
                           "mass": 0.001, "stiffness": { "planar": 90.22118, "inter_layer": 60.80123 },
                           "damping": { "planar": 0.06, "inter_layer": 0.06 } },
                "environment": { "air_retention": 0.97, "room": { "enabled": false } },
                "obstacles": [ )" +
                                  obstacle + R"( ],
                "contact": { "response": "friction", "radius": 0.01, "friction": 0.3 },
                "integrator": { "type": ")" +
                                  integrator + R"(", "dt": 0.03 },
                "run": { "duration": 1, "stop_at_rest": false } })"));
            const std::vector<Vec3> start = scene.system().particles.position;
            Real fastest = 0;
            for (int step = 0; step < 33; ++step)
            {
                ASSERT_NO_THROW(scene.step()) << "step " << step;
                for (const Vec3& v : scene.system().particles.velocity)
                {
                    fastest = std::max(fastest, v.norm());
                }
            }
            EXPECT_LT(fastest, 0.5);
            const std::vector<Vec3>& x = scene.system().particles.position;
            for (std::size_t i = 0; i < x.size(); ++i)
            {
                if (start[i].y() == -0.5)
                {
                    EXPECT_GE(x[i].y(), -0.5 - 1e-6) << "mass " << i << " sank into the box";
                    EXPECT_LE(x[i].y(), -0.5 + 1e-3) << "mass " << i << " left the box";
                }
            }
        }
    }
}

// A run whose duration ends before some actions' times says which never fired, in its output and its summary.
TEST(Scene, ARunSaysWhichActionsNeverFired)
{
    Scene scene(sceneFrom(R"({
        "sheet": { "size": "3x2x3" },
        "environment": { "room": { "enabled": false } },
        "integrator": { "type": "implicit", "dt": 0.03 },
        "script": [ { "time": 0.1, "action": "gravity", "value": [0, 0, 0], "label": "weightless" },
                    { "time": 5.0, "action": "gravity", "value": [0, -1, 0], "label": "moon" } ],
        "run": { "duration": 0.3, "stop_at_rest": false } })"));
    RunOptions options;
    options.showProgress = false;
    std::ostringstream out;
    const RunResult result = runScene(scene, options, out);
    ASSERT_TRUE(result.summary.contains("unfired_actions"));
    ASSERT_EQ(result.summary["unfired_actions"].size(), 1u);
    EXPECT_EQ(result.summary["unfired_actions"][0]["label"], "moon");
    EXPECT_EQ(result.summary["unfired_actions"][0]["time"], 5.0);
    EXPECT_NE(out.str().find("never fired"), std::string::npos) << out.str();
    EXPECT_NE(out.str().find("moon"), std::string::npos) << out.str();
    EXPECT_EQ(out.str().find("weightless"), std::string::npos) << out.str();
}

// A glassy material sheet on the symplectic integrator needs thousands of substeps a step: the run says so before it
// starts, with the count, and names the implicit integrator; the same sheet on the implicit one says nothing.
TEST(Scene, ARunNeedingOverAThousandSubstepsSaysSoBeforeItStarts)
{
    const std::string json = R"({
        "sheet": { "size": "4x2x4", "min": [-0.1, 0, -0.1], "max": [0.1, 0.01, 0.1] },
        "material": { "file": "../materials/hips.json" },
        "environment": { "room": { "enabled": false } },
        "integrator": { "type": "INTEGRATOR", "dt": 0.03 },
        "run": { "duration": 0.03, "stop_at_rest": false } })";
    auto output = [&](const std::string& integrator)
    {
        std::string text = json;
        text.replace(text.find("INTEGRATOR"), 10, integrator);
        Scene scene(sceneFrom(text));
        EXPECT_EQ(scene.substepWarning().empty(), integrator == "implicit") << integrator;
        RunOptions options;
        options.showProgress = false;
        std::ostringstream out;
        runScene(scene, options, out);
        return out.str();
    };
    const std::string symplectic = output("symplectic");
    EXPECT_NE(symplectic.find("substeps"), std::string::npos) << symplectic;
    EXPECT_NE(symplectic.find("\"implicit\""), std::string::npos) << symplectic;
    EXPECT_EQ(output("implicit").find("substeps"), std::string::npos);
}
