// What the viewer does to a scene without drawing it: real-time stepping, pause and step, loading and rebuilding
// (keeping the previous scene on failure), the pick spring and its caps, per-mass scalars, screen regions.

#include "viewer/ViewerSession.h"
#include "viewer/FramePacing.h"
#include "viewer/MassScalars.h"
#include "viewer/PickSpring.h"
#include "viewer/RateMeter.h"
#include "viewer/ScreenRegions.h"
#include "viewer/StepScheduler.h"

#include "core/InputError.h"
#include "core/integrate/StabilityEstimate.h"
#include "scene/SceneFile.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <numeric>

using namespace masse;
using namespace masse::viewer;

namespace
{
std::string dropScenePath()
{
    return std::string(MASSE_SOURCE_DIR) + "/data/scenes/paper-drop.json";
}

scene::SceneSpec dropScene()
{
    return scene::loadScene(dropScenePath());
}

/// A scene file in the test's temporary folder.
std::string writeTemporary(const std::string& name, const std::string& text)
{
    const std::filesystem::path path = std::filesystem::temp_directory_path() / name;
    std::ofstream(path) << text;
    return path.string();
}
} // namespace

TEST(StepScheduler, SpendsBankedWallTimeInWholeSteps)
{
    StepScheduler scheduler(0.03);
    scheduler.addWallTime(0.1);
    int steps = 0;
    for (; scheduler.stepDue(); scheduler.stepTaken())
    {
        ++steps;
    }
    EXPECT_EQ(steps, 3);
    EXPECT_NEAR(scheduler.owed(), 0.01, 1e-12) << "the remainder carries over to the next frame";
    scheduler.addWallTime(0.025);
    EXPECT_TRUE(scheduler.stepDue());
}

TEST(StepScheduler, OwesNoMoreThanItsCapAndSaysWhenItDropsTime)
{
    // By default a hiccup of a second (a forming scene's first frame: 0.6 s at 64x2x64) is caught up, no more.
    StepScheduler catchingUp(0.03);
    EXPECT_FALSE(catchingUp.addWallTime(0.6));
    EXPECT_NEAR(catchingUp.owed(), 0.6, 1e-12);
    EXPECT_TRUE(catchingUp.addWallTime(0.6));
    EXPECT_NEAR(catchingUp.owed(), 1.0, 1e-12);

    StepScheduler scheduler(0.03, 0.25);
    EXPECT_FALSE(scheduler.addWallTime(0.2));
    EXPECT_TRUE(scheduler.addWallTime(5)) << "more than the cap is not caught up";
    EXPECT_NEAR(scheduler.owed(), 0.25, 1e-12);

    StepScheduler slow(0.5, 0.25);
    slow.addWallTime(1);
    EXPECT_TRUE(slow.stepDue()) << "a step longer than the cap still comes due";
}

TEST(RateMeter, PublishesRatesOncePerWindow)
{
    RateMeter meter(0.5);
    for (int i = 0; i < 7; ++i)
    {
        meter.add(0.0625, 1, 2, 0.03); // 16 frames/s, 32 steps/s, 0.48 s simulated per wall second
    }
    EXPECT_FALSE(meter.hasFigures());
    meter.add(0.0625, 1, 2, 0.03);
    ASSERT_TRUE(meter.hasFigures());
    EXPECT_NEAR(meter.framesPerSecond(), 16, 1e-9);
    EXPECT_NEAR(meter.stepsPerSecond(), 32, 1e-9);
    EXPECT_NEAR(meter.realTimeFactor(), 0.48, 1e-9);
    EXPECT_FALSE(meter.fellBehind());
    meter.add(0.25, 1, 1, 0.03, true);
    meter.add(0.25, 1, 1, 0.03);
    EXPECT_TRUE(meter.fellBehind()) << "a pass out of budget marks the window";
    meter.add(0.5, 1, 16, 0.48);
    EXPECT_FALSE(meter.fellBehind());
}

// While the scene runs, a frame comes for a new snapshot (at most about 30 a second) or for input, and the same picture
// is drawn again only every quarter of a second: a scene slower than the window leaves the cores to its steps.
TEST(FramePacing, TheSamePictureIsNotDrawnAgainWhileTheSceneRuns)
{
    FrameMoment moment;
    moment.newPicture = true;
    moment.sinceLastFrame = 0.025;
    EXPECT_FALSE(frameDue(moment)) << "a new picture waits for the frame-rate cap";
    moment.sinceLastFrame = 0.027;
    EXPECT_TRUE(frameDue(moment)) << "a new picture a little under 1/30 s after the last frame";
    moment.newPicture = false;
    EXPECT_FALSE(frameDue(moment)) << "the same picture again";
    moment.sinceLastFrame = 0.2;
    EXPECT_FALSE(frameDue(moment));
    moment.sinceLastFrame = 0.25;
    EXPECT_TRUE(frameDue(moment)) << "now and then, for the panel's timers";
    moment.sinceLastFrame = 0.001;
    moment.mustDraw = true;
    EXPECT_TRUE(frameDue(moment)) << "input, the first and the last frame come at once";
    moment.mustDraw = false;
    moment.paused = true;
    moment.sinceLastFrame = 0.017;
    EXPECT_TRUE(frameDue(moment)) << "paused, up to 60 frames a second";
    moment.sinceLastFrame = 0.01;
    EXPECT_FALSE(frameDue(moment));
}

TEST(ViewerSession, RunsInRealTimeWithinABudgetPerPass)
{
    ViewerSession session(dropScene());
    const Advance first = session.advance(0.1, 10);
    EXPECT_EQ(first.steps, 3);
    EXPECT_NEAR(session.scene().time(), 0.09, 1e-12);
    EXPECT_FALSE(first.behind);

    // A pass without budget takes no step; what it owes is taken by the next passes (a hiccup is caught up).
    const Advance starved = session.advance(0.2, 0);
    EXPECT_EQ(starved.steps, 0);
    EXPECT_FALSE(starved.behind);
    EXPECT_EQ(session.advance(0, 10).steps, 7);
    EXPECT_NEAR(session.scene().time(), 0.3, 1e-12);

    // Owing more than the cap (a second) drops the excess: slow motion, not a spiral.
    const Advance stalled = session.advance(2, 10);
    EXPECT_TRUE(stalled.behind);
    EXPECT_EQ(stalled.steps, 33);
}

TEST(ViewerSession, PauseHoldsTimeAndSingleStepsAdvanceByOneStep)
{
    ViewerSession session(dropScene());
    session.setPaused(true);
    EXPECT_EQ(session.advance(1, 10).steps, 0);
    session.requestStep();
    EXPECT_EQ(session.advance(1, 10).steps, 1);
    EXPECT_NEAR(session.scene().time(), 0.03, 1e-12);
    EXPECT_EQ(session.advanceSteps(5).steps, 0) << "fixed steps wait while paused";
    session.setPaused(false);
    EXPECT_EQ(session.advanceSteps(5).steps, 5);
}

TEST(ViewerSession, ResetStartsTheSceneAgainFromItsSpec)
{
    scene::SceneSpec spec = dropScene();
    spec.sheet.lattice.countX = 6;
    ViewerSession session(spec);
    session.advanceSteps(20);
    ASSERT_GT(session.scene().events().size(), 0u);
    const std::uint64_t generation = session.generation();
    session.reset();
    EXPECT_EQ(session.scene().time(), 0);
    EXPECT_TRUE(session.scene().events().empty());
    EXPECT_EQ(session.spec().sheet.lattice.countX, 6) << "the spec it runs, not the file's";
    EXPECT_GT(session.generation(), generation);
}

TEST(ViewerSession, AFileThatDoesNotLoadKeepsTheSceneAndShowsItsOwnError)
{
    ViewerSession session(dropScene());
    session.advanceSteps(3);
    const std::uint64_t generation = session.generation();

    EXPECT_FALSE(session.load("/nonexistent/scene.json"));
    EXPECT_NE(session.error().find("/nonexistent/scene.json"), std::string::npos) << session.error();
    EXPECT_EQ(session.generation(), generation);
    EXPECT_NEAR(session.scene().time(), 0.09, 1e-12) << "the scene runs on where it was";

    const std::string typo = writeTemporary("masse-view-typo.json", R"({ "sheet": { "sise": "8x2x8" } })");
    EXPECT_FALSE(session.load(typo));
    EXPECT_NE(session.error().find("sise"), std::string::npos) << "the loader's own message: " << session.error();
    EXPECT_EQ(session.spec().name, "paper-drop");

    EXPECT_TRUE(session.load(dropScenePath()));
    EXPECT_TRUE(session.error().empty());
    EXPECT_GT(session.generation(), generation);
    EXPECT_EQ(session.scene().time(), 0);
}

TEST(ViewerSession, RebuildsFromAnEditedSpecOrKeepsTheSceneWhenItCannot)
{
    ViewerSession session(dropScene());
    scene::SceneSpec spec = session.spec();
    spec.sheet.lattice.countX = 6;
    spec.sheet.lattice.countZ = 6;
    spec.time.integrator = IntegratorKind::ImplicitEuler;
    ASSERT_TRUE(session.rebuild(spec)) << session.error();
    EXPECT_EQ(session.scene().system().massCount(), 61u) << "paper Table 2: a 6x2x6 sheet has 61 masses";
    EXPECT_EQ(session.scene().simulator().settings().integrator, IntegratorKind::ImplicitEuler);

    spec.sheet.lattice.countX = 1;
    EXPECT_FALSE(session.rebuild(spec));
    EXPECT_NE(session.error().find("size"), std::string::npos) << session.error();
    EXPECT_EQ(session.scene().system().massCount(), 61u);
}

// A size typed into the panel that cannot make a sheet is the panel's mistake, not the scene file's: the message
// names the panel's field and not the file the scene came from.
TEST(ViewerSession, ABadSizeFromThePanelIsNamedAsThePanels)
{
    ViewerSession session(dropScene());
    scene::SceneSpec spec = session.spec();
    spec.sheet.lattice.layers = 70;
    spec.sheet.sizeGiven = "the panel's size";
    EXPECT_FALSE(session.rebuild(spec));
    EXPECT_EQ(session.error().rfind("the panel's size: ", 0), 0u) << session.error();
    EXPECT_EQ(session.error().find(".json"), std::string::npos) << session.error();
    EXPECT_NE(session.error().find("64 layers"), std::string::npos) << session.error();
}

// A step the integrator cannot take is bad input, refused when the scene is built (before any frame is drawn), so
// the viewer keeps the scene it showed (see ViewerApp's reset).
TEST(ViewerSession, AStepTooLargeIsRefusedWhenTheSceneIsBuilt)
{
    scene::SceneSpec spec = dropScene();
    spec.time.dt = 1000; // far more substeps than the simulator allows for an explicit integrator
    try
    {
        ViewerSession session(spec);
        ADD_FAILURE() << "a scene needing 1.5 million substeps a step was accepted";
    }
    catch (const InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("substeps"), std::string::npos) << e.what();
    }
}

TEST(ViewerSession, PickSpringFollowsTheCursorAndGoesOnRelease)
{
    ViewerSession session(dropScene());
    MassSpringSystem& system = session.scene().system();
    const std::uint64_t revision = system.revision;
    session.beginPick(10, Vec3(0, 1, 0));
    ASSERT_EQ(system.userSprings.size(), 1u);
    EXPECT_GT(system.revision, revision) << "the integrator's cached state learns of the new spring";
    EXPECT_EQ(session.pickedMass(), std::optional<Index>(10));
    session.movePick(Vec3(0.5, 1, 0));
    EXPECT_EQ(system.userSprings.all()[0].target, Vec3(0.5, 1, 0));
    EXPECT_EQ(session.pickTarget(), std::optional<Vec3>(Vec3(0.5, 1, 0)));
    session.endPick();
    EXPECT_EQ(system.userSprings.size(), 0u);
    EXPECT_FALSE(session.pickedMass());

    session.beginPick(3, Vec3::Zero());
    session.reset();
    EXPECT_FALSE(session.pickedMass()) << "a reset drops the pick with the old state";
    EXPECT_EQ(session.scene().system().userSprings.size(), 0u);
}

TEST(PickSpring, StaysBelowTheSheetsStiffestModeAndLiftsNoMoreThanTwiceItsWeight)
{
    const scene::Scene scene(dropScene());
    const MassSpringSystem& system = scene.system();
    const UserSpring spring = makePickSpring(system, 20, Vec3(0, 2, 0));
    const Real sheetFrequency = estimateStability(system, IntegratorKind::SymplecticEuler, 1).highestFrequency;
    const Real m = system.particles.mass[20];
    EXPECT_NEAR(std::sqrt(spring.stiffness / m), 0.25 * sheetFrequency, 1e-9 * sheetFrequency);
    EXPECT_NEAR(spring.damping / (2 * std::sqrt(spring.stiffness * m)), 0.7, 1e-12);
    const Real weight =
        std::accumulate(system.particles.mass.begin(), system.particles.mass.end(), Real(0)) * standardGravity;
    EXPECT_NEAR(spring.maxForce, 2 * weight, 1e-12);
    // However far the cursor, the pull is capped.
    const UserSpringForce far = evaluateUserSpring(spring, Vec3(0, -100, 0), Vec3::Zero());
    EXPECT_NEAR(far.force.norm(), spring.maxForce, 1e-9);
}

TEST(PickSpring, AFarCursorLiftsTheSheetWithoutUpsettingAnyIntegrator)
{
    // The viewer's integrator list offers all of these (Panel.cpp); each must carry a drag.
    for (IntegratorKind kind :
         {IntegratorKind::SymplecticEuler, IntegratorKind::ImplicitEuler, IntegratorKind::Bdf2, IntegratorKind::TrBdf2})
    {
        scene::SceneSpec spec = dropScene();
        spec.time.integrator = kind;
        ViewerSession session(spec);
        const int substepsBefore = session.scene().simulator().substepsFor(spec.time.dt);
        // The middle of the bottom layer, pulled toward a point 5 m overhead: far beyond where the cap engages.
        const Index middle = session.scene().lattice().index(0, 4, 4);
        const Real startHeight = session.scene().system().particles.position[middle].y();
        session.beginPick(middle, Vec3(0.3, 5.3, 0.3));
        EXPECT_LE(session.scene().simulator().substepsFor(spec.time.dt), int(std::ceil(1.05 * substepsBefore)))
            << "picking barely changes the explicit substep";
        session.advanceSteps(40); // 1.2 s
        ASSERT_TRUE(session.error().empty()) << session.error();
        const Particles& particles = session.scene().system().particles;
        Real fastest = 0;
        for (const Vec3& v : particles.velocity)
        {
            ASSERT_TRUE(v.allFinite());
            fastest = std::max(fastest, v.norm());
        }
        EXPECT_LT(fastest, 10) << integratorName(kind) << ": a capped pull accelerates the sheet gently";
        EXPECT_GT(particles.position[middle].y(), startHeight + 0.2) << integratorName(kind) << ": and lifts it";
    }
}

TEST(MassScalars, RegistryFindsReplacesAndNamesScalars)
{
    MassScalarRegistry registry = standardMassScalars();
    for (const char* name : {"speed", "strain", "temperature", "thickness", "thickness_ratio"})
    {
        ASSERT_TRUE(registry.find(name)) << name;
    }
    EXPECT_FALSE(registry.find("stress"));
    // A model adds its field by name, and the panel lists it; the same name again replaces it.
    registry.add({"stress", "Pa", "", [](const scene::Scene& s, std::vector<float>& values) {
                      values.assign(s.system().massCount(), 1.0f);
                  }});
    EXPECT_EQ(registry.names(), "speed, strain, temperature, thickness, thickness_ratio, stress");
    registry.add({"stress", "MPa", "", {}});
    EXPECT_EQ(registry.all().size(), 6u);
    EXPECT_EQ(registry.find("stress")->unit, "MPa");
}

TEST(MassScalars, SpeedAndStrainReadTheSheet)
{
    scene::Scene scene(dropScene());
    MassSpringSystem& system = scene.system();
    std::vector<float> values;
    standardMassScalars().find("strain")->evaluate(scene, values);
    ASSERT_EQ(values.size(), system.massCount());
    for (float v : values)
    {
        EXPECT_NEAR(v, 0, 1e-6) << "at rest length";
    }
    // Stretched 10% in every direction about the sheet's corner, every spring is 10% long.
    const Vec3 corner = system.particles.position[0];
    for (Vec3& x : system.particles.position)
    {
        x = corner + 1.1 * (x - corner);
    }
    meanSpringStrain(system, values);
    for (float v : values)
    {
        EXPECT_NEAR(v, 0.1, 1e-5);
    }
    system.particles.velocity[7] = Vec3(3, 4, 0);
    standardMassScalars().find("speed")->evaluate(scene, values);
    EXPECT_NEAR(values[7], 5, 1e-6);
    EXPECT_EQ(values[8], 0);
    const ScalarRange range = rangeOf(values);
    EXPECT_EQ(range.low, 0);
    EXPECT_EQ(range.high, 5);
    const ScalarRange flat = rangeOf(std::vector<float>(4, 2.0f));
    EXPECT_GT(flat.high, flat.low) << "a flat field still maps to colours";
}

TEST(ScreenRegions, BoxesCoverTheProjectedPointsWithinTheWindow)
{
    OrbitCamera camera;
    camera.target = Vec3::Zero();
    camera.distance = 5;
    const Viewport window{400, 300};
    const auto box = screenBox(camera, window, {Vec3(-0.5, -0.5, 0), Vec3(0.5, 0.5, 0)});
    ASSERT_TRUE(box);
    EXPECT_LT(box->left, 200);
    EXPECT_GT(box->right, 200);
    EXPECT_LT(box->top, 150);
    EXPECT_GT(box->bottom, 150);
    EXPECT_NEAR(box->left + box->right, 400, 1e-9) << "symmetric about the middle";
    const auto clipped = screenBox(camera, window, {Vec3(-100, -0.5, 0), Vec3(0, 0.5, 0)});
    ASSERT_TRUE(clipped);
    EXPECT_EQ(clipped->left, 0);
    EXPECT_FALSE(screenBox(camera, window, {Vec3(0, 0, 10)})) << "behind the eye";
    EXPECT_FALSE(screenBox(camera, window, {Vec3(100, 0, 0)})) << "off the window";
}

TEST(ScreenRegions, NameThePolyhedraAndWhetherTheyWereTouched)
{
    scene::Scene scene(dropScene());
    OrbitCamera camera;
    camera.target = Vec3(0.3, -0.9, 0.3);
    camera.pitch = 0.4;
    camera.distance = 6;
    const nlohmann::json before = screenRegions(scene, camera, {800, 600});
    ASSERT_EQ(before["obstacles"].size(), 2u) << "the block and the wedge; the room is not listed";
    EXPECT_EQ(before["obstacles"][0]["name"], "block");
    EXPECT_FALSE(before["obstacles"][0]["touched"].get<bool>());
    EXPECT_TRUE(before["sheet"].is_array());
    while (scene.eventTime("contact", "block") < 0 && scene.time() < 2)
    {
        scene.step();
    }
    EXPECT_TRUE(screenRegions(scene, camera, {800, 600})["obstacles"][0]["touched"].get<bool>());
}

// --compare: the session runs the scene beside Bullet's twin, stepping both, and keeps doing so across a reset.
TEST(ViewerSession, CompareModeStepsTheBulletTwinWithTheScene)
{
    scene::SceneSpec spec = scene::loadScene(std::string(MASSE_SOURCE_DIR) + "/data/scenes/box-landing.json");
    spec.sheet.lattice.countX = 4;
    spec.sheet.lattice.countZ = 4;
    ViewerSession session(spec, true);
    ASSERT_NE(session.comparison(), nullptr);
    const std::size_t nodes = session.comparison()->twin(0).nodeCount();
    EXPECT_EQ(nodes, session.scene().system().massCount());
    const Vec3 start = session.comparison()->twin(0).position(0);
    session.advanceSteps(10);
    EXPECT_NEAR(session.scene().time(), 10 * spec.time.dt, 1e-9);
    EXPECT_NEAR(session.comparison()->twin(0).time(), session.scene().time(), 1e-9);
    EXPECT_LT(session.comparison()->twin(0).position(0).y(), start.y()); // it fell too
    session.reset();
    ASSERT_NE(session.comparison(), nullptr);
    EXPECT_EQ(session.comparison()->twin(0).time(), 0.0);
}
