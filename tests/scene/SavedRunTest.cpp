// A live run saved as a scene file (scene/SavedRun.h) replays bit for bit, and the process actions it records
// (pressure, steer, heater power, obstacle_temperature) act as they say and are refused where they cannot act.

#include "support/TestThreads.h"

#include "core/InputError.h"
#include "core/StateHash.h"
#include "scene/SavedRun.h"
#include "scene/Scene.h"
#include "scene/SceneFile.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

using namespace masse;
using namespace masse::scene;

namespace
{
const std::string source = MASSE_SOURCE_DIR;

RunSource sourceOf(const std::string& file, const std::string& size)
{
    RunSource run;
    run.path = source + "/data/scenes/" + file;
    run.flags.size = size;
    run.flags.settings = {"output.frames_every=0"};
    return run;
}

SceneSpec specOf(const RunSource& run)
{
    SceneSpec spec = loadScene(run.path, run.flags);
    return spec;
}

ScriptAction pressureAction(Real time, Real pressure, Real ramp)
{
    ScriptAction a;
    a.kind = ScriptAction::Kind::Pressure;
    a.time = time;
    a.pressure = pressure;
    a.ramp = ramp;
    return a;
}

ScriptAction steerAction(Real time, const std::string& obstacle, const Vec3& to, Real speed)
{
    ScriptAction a;
    a.kind = ScriptAction::Kind::Steer;
    a.time = time;
    a.obstacle = obstacle;
    a.target = to;
    a.speed = speed;
    return a;
}

ScriptAction temperatureAction(Real time, const std::string& obstacle, Real celsius)
{
    ScriptAction a;
    a.kind = ScriptAction::Kind::ObstacleTemperature;
    a.time = time;
    a.obstacle = obstacle;
    a.temperature = celsius + 273.15;
    return a;
}

void stepTo(Scene& scene, Real time)
{
    while (scene.time() < time - 1e-9)
    {
        scene.step();
    }
}

/// The scene the document describes, run to its end: the state hash and the time it ended at.
std::pair<std::uint64_t, Real> replay(const nlohmann::json& document)
{
    Scene scene(parseScene(document, source + "/data/scenes", "saved run"));
    while (!scene.finished())
    {
        scene.step();
    }
    return {stateHash(scene.system().particles), scene.time()};
}
} // namespace

// Every recorded action's fields come back from its script item to the last bit.
TEST(SavedRun, ActionsReadBackAsTheyWereWritten)
{
    ScriptAction heater;
    heater.kind = ScriptAction::Kind::Heater;
    heater.time = 0.1 + 0.2; // 0.30000000000000004
    heater.heater = "top";
    heater.on = false;
    heater.power = 1234.5678;
    ScriptAction ambient;
    ambient.kind = ScriptAction::Kind::Ambient;
    ambient.time = 1.0 / 3;
    ambient.temperature = 0.1 + 273.15 + 1e-13;
    const std::vector<ScriptAction> actions = {pressureAction(0.7, -81234.56789, 0.25),
                                               steerAction(1.0 / 7, "plug", Vec3(0.1, -0.0451, 1.0 / 3), 0.055),
                                               temperatureAction(2.0 / 3, "mould", 71.3), heater, ambient};
    for (const ScriptAction& a : actions)
    {
        const nlohmann::json item = actionDocument(a);
        const ScriptAction b = readScriptAction(nlohmann::json::parse(item.dump()), "script[0]");
        EXPECT_EQ(b.kind, a.kind) << item.dump();
        EXPECT_EQ(b.time, a.time) << item.dump();
        EXPECT_EQ(b.pressure, a.pressure) << item.dump();
        EXPECT_EQ(b.ramp, a.ramp) << item.dump();
        EXPECT_EQ(b.obstacle, a.obstacle) << item.dump();
        EXPECT_EQ(b.target, a.target) << item.dump();
        EXPECT_EQ(b.speed, a.speed) << item.dump();
        EXPECT_EQ(b.temperature, a.temperature) << item.dump();
        EXPECT_EQ(b.heater, a.heater) << item.dump();
        EXPECT_EQ(b.on, a.on) << item.dump();
        EXPECT_EQ(b.power, a.power) << item.dump();
    }
}

// The forming bench's promise: the plug-assist cup at 16x2x16 handled live (the plug stopped early and sent down
// again faster, the vacuum switched on early at another level, the mould warmed), saved, and replayed from the saved
// file, ends at the same time in the same state, bit for bit, at 1 and 2 threads.
TEST(SavedRun, ALiveRunReplaysBitForBit)
{
    const RunSource run = sourceOf("plug-assist-cup.json", "16x2x16");
    Scene live(specOf(run));
    stepTo(live, 0.3);
    live.addAction(steerAction(live.time(), "plug", Vec3(0, 0.0, 0), 0.02)); // stop short
    stepTo(live, 0.5);
    live.addAction(steerAction(live.time(), "plug", Vec3(0, -0.05, 0), 0.1));
    live.addAction(pressureAction(live.time(), 60000, 0.2));
    stepTo(live, 0.62);
    live.addAction(temperatureAction(live.time(), "mould", 80));
    stepTo(live, 0.9);
    live.addAction(pressureAction(live.time(), 0, 0));
    stepTo(live, 1.0);
    const std::uint64_t liveHash = stateHash(live.system().particles);
    const Real savedAt = live.time();
    ASSERT_EQ(live.addedActions().size(), 5u);

    const nlohmann::json document = savedRunDocument(run, live.addedActions(), savedAt);
    EXPECT_EQ(document["script"].size(), 5u);
    EXPECT_EQ(document["run"]["duration"].get<Real>(), savedAt);
    for (int threads : {1, 2})
    {
        const test::BoundPool pool(threads);
        const auto [hash, end] = replay(document);
        EXPECT_EQ(end, savedAt) << threads << " threads";
        EXPECT_EQ(hash, liveHash) << threads << " threads";
    }
    // The actions did something: the same run without them ends elsewhere.
    const auto [untouched, end] = replay(savedRunDocument(run, {}, savedAt));
    EXPECT_NE(untouched, liveHash);
}

// A pressure action replaces the schedule from its time: the cup's vacuum, due to reach 80 kPa at 1 s, goes from
// what it was to 30 kPa over 0.1 s and holds there. A steer sends the plug from where it is straight to its target at
// its speed and holds it there. A heater action's power is the heater's from then on; an obstacle's temperature is
// the contact heat's.
TEST(SavedRun, ProcessActionsDoWhatTheySay)
{
    RunSource run = sourceOf("plug-assist-cup.json", "12x2x12");
    run.flags.dt = "0.01"; // steps that land on the times below
    Scene cup(specOf(run));
    stepTo(cup, 0.2);
    const int plug = cup.environment().findObstacle("plug");
    const Vec3 start = cup.environment().obstacle(plug).pose.position;
    cup.addAction(pressureAction(cup.time(), 30000, 0.1));
    cup.addAction(steerAction(cup.time(), "plug", start + Vec3(0, -0.01, 0), 0.05)); // 10 mm at 50 mm/s: 0.2 s
    cup.addAction(temperatureAction(cup.time(), "mould", 85));
    const Real fired = cup.time();
    cup.step();
    EXPECT_NEAR(cup.formingPressure(), 30000 * (cup.time() - fired) / 0.1, 1e-6);
    stepTo(cup, fired + 0.1);
    EXPECT_NEAR(cup.formingPressure(), 30000, 1e-9);
    EXPECT_NEAR(cup.obstacleTemperature(cup.environment().findObstacle("mould")), 85 + 273.15, 1e-12);
    EXPECT_NEAR(cup.environment().obstacle(plug).pose.position.y(), start.y() - 0.005, 1e-9) << "halfway at 0.1 s";
    stepTo(cup, fired + 0.3);
    EXPECT_NEAR(cup.environment().obstacle(plug).pose.position.y(), start.y() - 0.01, 1e-12);
    EXPECT_NEAR(cup.formingPressure(), 30000, 1e-9) << "the rest of the schedule (80 kPa at 1.5 s) is replaced";
    stepTo(cup, 1.6);
    EXPECT_NEAR(cup.formingPressure(), 30000, 1e-9);
}

// Where an action cannot act, the scene file is refused naming the item: a pressure without a "forming" section, a
// steer of a static obstacle or at no speed, an obstacle's temperature without heat.
TEST(SavedRun, ProcessActionsAreRefusedWhereTheyCannotAct)
{
    const auto refusal = [](const std::string& file, const nlohmann::json& action)
    {
        nlohmann::json document = readSceneDocument(source + "/data/scenes/" + file);
        document["script"] = nlohmann::json::array({action});
        try
        {
            parseScene(document, source + "/data/scenes", file);
        }
        catch (const InputError& e)
        {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_NE(refusal("sag.json", {{"action", "pressure"}, {"pressure", 1000}}).find("script[0].action"),
              std::string::npos);
    EXPECT_NE(refusal("vacuum-forming-cup.json",
                      {{"action", "steer"}, {"obstacle", "mould"}, {"to", {0, 0, 0}}, {"speed", 0.1}})
                  .find("script[0].obstacle: 'mould' is static"),
              std::string::npos);
    EXPECT_NE(
        refusal("plug-assist-cup.json", {{"action", "steer"}, {"obstacle", "plug"}, {"to", {0, 0, 0}}, {"speed", 0}})
            .find("script[0].speed"),
        std::string::npos);
    EXPECT_NE(
        refusal("paper-drop.json", {{"action", "obstacle_temperature"}, {"obstacle", "block"}, {"temperature_c", 50}})
            .find("script[0].action"),
        std::string::npos);
    EXPECT_NE(refusal("plug-assist-cup.json",
                      {{"action", "obstacle_temperature"}, {"obstacle", "mold"}, {"temperature_c", 50}})
                  .find("did you mean 'mould'"),
              std::string::npos);
    EXPECT_EQ(refusal("plug-assist-cup.json", {{"action", "pressure"}, {"pressure", 50000}, {"ramp", 0.2}}), "");
}
