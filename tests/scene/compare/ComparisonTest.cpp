// MaSSE and its Bullet twin side by side (scene::Comparison, behind `masse compare`): each engine's figures are its
// own, measured as an independent run of that engine alone would be; the scene's script reaches the twin.

#include "scene/compare/Comparison.h"
#include "bridge/SoftBodyTwin.h"
#include "scene/SceneFile.h"
#include "scene/compare/CompareMetrics.h"
#include "scene/compare/ObstacleProbe.h"

#include "core/InputError.h"

#include <gtest/gtest.h>

using namespace masse;
using namespace masse::scene;

namespace
{
const std::string source = MASSE_SOURCE_DIR;

/// The reference landing, cut short for test time: the 8 x 2 x 8 Table 1 sheet falls 0.8 m onto the box at
/// dt = 0.03 s, for 1.5 s (50 frames), not stopping at rest.
SceneSpec shortLanding()
{
    SceneSpec spec = loadScene(source + "/data/scenes/box-landing.json");
    spec.run.duration = 1.5;
    spec.run.stopAtRest = false;
    return spec;
}

/// One engine alone, measured after every frame as the comparison measures: signed distances from the scene's
/// environment, spheres of the contact radius, tunnels, kinetic energy.
struct Alone
{
    PenetrationStats penetration{0.01};
    TunnelCount tunnels;
    std::vector<Real> energy;
    std::vector<Vec3> finalPositions;
};

template <typename Step, typename Positions, typename Energy>
Alone measureAlone(bridge::BulletEnvironment& environment, int frames, Step&& step, Positions&& positions,
                   Energy&& energy)
{
    Alone alone;
    const Real search = 0.1;
    const std::vector<Vec3> start = positions();
    TunnelCounter tunnels(start, signedDistances(environment, start, search), obstacleQuery(environment));
    for (int f = 0; f < frames; ++f)
    {
        step();
        const std::vector<Vec3> x = positions();
        const std::vector<Real> d = signedDistances(environment, x, search);
        alone.penetration.addFrame(d);
        tunnels.addFrame(x, d);
        alone.energy.push_back(energy());
    }
    alone.tunnels = tunnels.count();
    alone.finalPositions = positions();
    return alone;
}

bool hasApproximation(const Comparison& comparison, const std::string& subject, const std::string& words)
{
    for (const Approximation& a : comparison.approximations())
    {
        if (a.subject == subject && a.message.find(words) != std::string::npos)
        {
            return true;
        }
    }
    return false;
}
} // namespace

// The figures of each column come from that engine: MaSSE's penetration, tunnels and energy equal those of the
// scene run alone, and each Bullet run's those of a twin with its piterations run alone (both deterministic, so
// exactly); compare.json carries the same numbers under the right engine, and the distance between the sheets is
// that of the two lone runs' final positions. On this landing Bullet penetrates more than MaSSE (measured: MaSSE
// 0 m, Bullet about 0.02 m), which a mix-up of columns would show.
TEST(Comparison, EachEngineReportsItsOwnMeasurements)
{
    const SceneSpec spec = shortLanding();
    CompareOptions options;
    options.bulletIterations = {1, 4};
    Comparison comparison(spec, options);
    comparison.run();
    const int frames = int(comparison.frameTimes().size());
    ASSERT_EQ(frames, 50);
    ASSERT_EQ(comparison.results().size(), 3u);

    Scene scene(spec);
    const Alone masse = measureAlone(
        scene.environment(), frames, [&] { scene.step(); }, [&] { return scene.system().particles.position; },
        [&] { return scene.kineticEnergy(); });
    std::vector<Alone> bullet;
    for (int n : options.bulletIterations)
    {
        Scene start(spec);
        bridge::SoftBodyTwinSettings settings = spec.bullet.settings;
        settings.piterations = n;
        bridge::SoftBodyTwin twin(start.system(), start.environment(), spec.contact, spec.time.dt, settings);
        bullet.push_back(measureAlone(
            start.environment(), frames, [&] { twin.step(); }, [&] { return twin.positions(); },
            [&] { return twin.kineticEnergy(); }));
    }

    const nlohmann::json report = comparison.report();
    const nlohmann::json& engines = report["engines"];
    ASSERT_EQ(engines.size(), 3u);
    auto check = [&](std::size_t k, const Alone& alone, const char* engine)
    {
        const EngineResult& r = comparison.results()[k];
        EXPECT_EQ(engines[k]["engine"], engine);
        EXPECT_EQ(r.penetration.max(), alone.penetration.max()) << r.label;
        EXPECT_EQ(r.penetration.mean(), alone.penetration.mean()) << r.label;
        EXPECT_EQ(r.tunnels.tunnelled(), alone.tunnels.tunnelled()) << r.label;
        EXPECT_EQ(r.tunnels.entered, alone.tunnels.entered) << r.label;
        EXPECT_EQ(r.run.kineticEnergy, alone.energy) << r.label;
        EXPECT_EQ(engines[k]["penetration"]["max"].get<double>(), alone.penetration.max()) << r.label;
        EXPECT_EQ(engines[k]["penetration"]["mean"].get<double>(), alone.penetration.mean()) << r.label;
        EXPECT_EQ(engines[k]["tunnelled"]["count"].get<std::size_t>(), alone.tunnels.tunnelled()) << r.label;
        EXPECT_EQ(engines[k]["kinetic_energy"]["final"].get<double>(), alone.energy.back()) << r.label;
        EXPECT_EQ(engines[k]["frames"], frames);
    };
    check(0, masse, "masse");
    EXPECT_EQ(engines[0]["label"], "MaSSE (symplectic)");
    for (std::size_t j = 0; j < bullet.size(); ++j)
    {
        check(j + 1, bullet[j], "bullet");
        EXPECT_EQ(engines[j + 1]["settings"]["piterations"], options.bulletIterations[j]);
        EXPECT_EQ(engines[j + 1]["label"], "Bullet (piterations=" + std::to_string(options.bulletIterations[j]) + ")");
        const PositionDistance d = positionDistance(masse.finalPositions, bullet[j].finalPositions);
        EXPECT_EQ(engines[j + 1]["distance_to_masse"]["final"]["rms"].get<double>(), d.rms);
        EXPECT_EQ(engines[j + 1]["distance_to_masse"]["final"]["max"].get<double>(), d.max);
        EXPECT_GT(bullet[j].penetration.max(), masse.penetration.max() + 0.005) << options.bulletIterations[j];
    }
    std::printf(
        "Table 1 sheet landing on a box, 1.5 s: max penetration MaSSE %.3g m, Bullet 1 pass %.3g m, 4 passes %.3g m\n",
        masse.penetration.max(), bullet[0].penetration.max(), bullet[1].penetration.max());
}

// The script reaches the twin. A 3 x 2 x 3 sheet in the air, without obstacles: at t = 0 its corner mass 8 is
// pinned, at 0.3 s the opposite corner (mass 0) is grabbed and pulled over 0.6 s to where turning the sheet 30 degrees
// up about the pin would put it (no stretch or bend needed to get there), and at 1.2 s gravity is switched off. After 2
// s, in both engines the grabbed mass is within 0.02 m of the path's end; the pinned node has not moved; the twin's
// gravity is the script's; and the approximations name the grab and the pin.
TEST(Comparison, MirrorsGrabsPinsAndGravityOntoTheTwin)
{
    const nlohmann::json document = nlohmann::json::parse(R"({
      "sheet": { "size": "3x2x3", "min": [-0.2, -0.49, -0.2], "max": [0.2, -0.39, 0.2] },
      "environment": { "room": { "enabled": false } },
      "integrator": { "type": "implicit", "dt": 0.03 },
      "run": { "duration": 2, "stop_at_rest": false },
      "bullet": { "substeps": 4 },
      "script": [
        { "time": 0, "action": "pin", "masses": { "masses": [8] } },
        { "time": 0.3, "action": "grab", "label": "hand", "mass": 0, "stiffness": 20, "max_force": 5,
          "path": [ { "time": 0.3, "position": [-0.2, -0.49, -0.2] },
                    { "time": 0.9, "position": [-0.146, -0.207, -0.146] } ] },
        { "time": 1.2, "action": "gravity", "value": [0, 0, 0] }
      ]
    })");
    const SceneSpec spec = parseScene(document, source, "script-mirror");
    Comparison comparison(spec, CompareOptions{});
    const Vec3 pinnedAt = comparison.twin(0).position(8);
    comparison.run();
    const bridge::SoftBodyTwin& twin = comparison.twin(0);
    const Vec3 target(-0.146, -0.207, -0.146);
    EXPECT_LT((twin.position(0) - target).norm(), 0.02) << twin.position(0).transpose();
    EXPECT_LT((comparison.scene().system().particles.position[0] - target).norm(), 0.02);
    std::printf("grabbed mass from its target: MaSSE %.3g m, Bullet %.3g m\n",
                (comparison.scene().system().particles.position[0] - target).norm(),
                (twin.position(0) - target).norm());
    EXPECT_TRUE(twin.pinned(8));
    EXPECT_EQ(twin.position(8), pinnedAt);
    EXPECT_EQ(twin.gravity(), Vec3::Zero());
    EXPECT_TRUE(hasApproximation(comparison, "script.grab", "same index"));
    EXPECT_TRUE(hasApproximation(comparison, "script.pin", "massless"));
}

// A scripted move of a kinematic box reaches the twin's copy of the box: a 3 x 2 x 3 sheet lying on the box is
// carried 0.1 m up between 0.3 s and 0.8 s, and after 1.5 s the bottom layer rests one contact radius above the new
// top (y = -0.39) in both engines, within 3 mm.
TEST(Comparison, MirrorsObstacleMovesOntoTheTwin)
{
    const nlohmann::json document = nlohmann::json::parse(R"({
      "sheet": { "size": "3x2x3", "min": [-0.2, -0.49, -0.2], "max": [0.2, -0.39, 0.2] },
      "environment": { "room": { "enabled": false } },
      "obstacles": [ { "name": "lift", "type": "box", "position": [0, -1, 0], "half_extents": [1, 0.5, 1],
                       "path": [ { "time": 0, "position": [0, -1, 0] } ] } ],
      "integrator": { "type": "implicit", "dt": 0.03 },
      "run": { "duration": 1.5, "stop_at_rest": false },
      "bullet": { "substeps": 4 },
      "script": [
        { "time": 0.3, "action": "move", "obstacle": "lift",
          "path": [ { "time": 0.3, "position": [0, -1, 0] }, { "time": 0.8, "position": [0, -0.9, 0] } ] }
      ]
    })");
    Comparison comparison(parseScene(document, source, "move-mirror"), CompareOptions{});
    comparison.run();
    for (Index i = 0; i < 9; ++i) // the bottom layer
    {
        EXPECT_NEAR(comparison.twin(0).position(i).y(), -0.39, 0.003) << i;
        EXPECT_NEAR(comparison.scene().system().particles.position[i].y(), -0.39, 0.003) << i;
    }
}

// Options the comparison cannot run with are refused before anything runs, naming the flag.
TEST(Comparison, RefusesBadOptions)
{
    auto refusal = [](const CompareOptions& options)
    {
        try
        {
            validate(options);
        }
        catch (const InputError& e)
        {
            return std::string(e.what());
        }
        return std::string("(accepted)");
    };
    CompareOptions zero;
    zero.bulletIterations = {1, 0};
    EXPECT_EQ(refusal(zero), "--bullet-iterations: each count must be a whole number in [1, 1000] (got 0)");
    CompareOptions twice;
    twice.bulletIterations = {4, 2, 4};
    EXPECT_EQ(refusal(twice), "--bullet-iterations: 4 is given twice");
    CompareOptions many;
    many.bulletSubsteps = 20000;
    EXPECT_EQ(refusal(many), "--bullet-substeps: must be a whole number in [1, 10000] (got 20000)");
}
