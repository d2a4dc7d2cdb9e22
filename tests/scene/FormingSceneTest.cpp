// Heat in scenes: a drape-forming run conserves the sheet's material and freezes what touches the cold mould.

#include "support/TestSystems.h"

#include "scene/GuardBounds.h"
#include "scene/Scene.h"
#include "scene/SceneFile.h"

#include "core/InputError.h"
#include "core/lattice/LatticeSurface.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <memory>

using namespace masse;
using namespace masse::scene;

namespace
{
const std::string source = MASSE_SOURCE_DIR;

/// The drape-forming scene at a coarser size, to keep the test quick.
SceneSpec formingScene(const std::string& size)
{
    nlohmann::json document = readSceneDocument(source + "/data/scenes/drape-forming.json");
    document["sheet"]["size"] = size;
    document.erase("output");
    return parseScene(document, source + "/data/scenes", "drape-forming (" + size + ")");
}

/// The bottom layer's surface area from its triangles, independently of SheetThickness.
Real surfaceArea(const Scene& scene)
{
    Real area = 0;
    const std::vector<Vec3>& x = scene.system().particles.position;
    for (const Triangle& t : layerTriangles(scene.lattice(), 0))
    {
        area += 0.5 * (x[t[1]] - x[t[0]]).cross(x[t[2]] - x[t[0]]).norm();
    }
    return area;
}
} // namespace

// Mass conservation, h = h0 A0 / A: through the whole run (heating, sag, forming over the mould, cooling) the
// volume sum h_i A_i stays h0 A0 within 0.5%, and the areas A_i it uses add up to the deformed bottom surface's
// own area (its triangles, computed here) within 0.5%, so the thickness is not conserved by mere bookkeeping.
TEST(FormingScene, VolumeIsConservedThroughAFormingRun)
{
    Scene scene(formingScene("10x2x10"));
    const SheetThickness& thickness = *scene.thickness();
    const Real restArea = surfaceArea(scene);
    Real worstVolume = 0;
    Real worstArea = 0;
    Real largestStretch = 0;
    while (!scene.finished())
    {
        scene.step();
        if (scene.steps() % 50 != 0)
        {
            continue;
        }
        worstVolume = std::max(worstVolume, std::abs(thickness.volume() / thickness.restVolume() - 1));
        Real bottomArea = 0;
        for (Index i = scene.lattice().layerStart[0]; i < scene.lattice().layerStart[1]; ++i)
        {
            bottomArea += thickness.area()[i];
        }
        const Real actual = surfaceArea(scene);
        worstArea = std::max(worstArea, std::abs(bottomArea / actual - 1));
        largestStretch = std::max(largestStretch, actual / restArea - 1);
    }
    EXPECT_LT(worstVolume, 0.005);
    EXPECT_LT(worstArea, 0.005);
    EXPECT_GT(largestStretch, 0.05) << "the sheet was not really formed"; // the mould stretches it by more than 5%
    EXPECT_LT(thickness.minimumThickness(), 0.9 * thickness.initialThickness());
}

// Sticky contact with a cold (40 C) mould: every mass that touched it stays put once the mould stops, and has
// cooled below the glass transition (ABS, 110 C) by the end while the free walls stayed hotter.
TEST(FormingScene, ColdMouldFreezesWhatItTouches)
{
    Scene scene(formingScene("10x2x10"));
    std::vector<Vec3> afterStop;
    while (!scene.finished())
    {
        scene.step();
        if (afterStop.empty() && scene.time() >= 41.0)
        {
            afterStop = scene.system().particles.position;
        }
    }
    const std::vector<std::uint8_t>& stuck = scene.contact().stuck();
    const std::vector<Real>& temperature = scene.thermal()->temperature();
    const Real glassTransition = scene.spec().material.material.glassTransition;
    int frozen = 0;
    Real hottestFree = 0;
    for (std::size_t i = 0; i < stuck.size(); ++i)
    {
        if (stuck[i])
        {
            ++frozen;
            EXPECT_EQ(scene.system().particles.position[i], afterStop[i]) << "stuck mass " << i << " moved";
            EXPECT_LT(temperature[i], glassTransition) << "mass " << i;
        }
        else if (!scene.system().particles.pinned[i])
        {
            hottestFree = std::max(hottestFree, temperature[i]);
        }
    }
    EXPECT_GT(frozen, 5);
    EXPECT_GT(hottestFree, glassTransition - 30); // the walls cool more slowly, in air
    EXPECT_GE(scene.eventTime("contact", "mould"), 36.0);
}

TEST(FormingScene, BadHeatInputIsRefusedWithItsKey)
{
    auto errorOf = [](const std::string& json)
    {
        return masse::test::inputErrorOf(
            [&] { Scene scene(parseScene(nlohmann::json::parse(json), source + "/data/scenes", "inline")); });
    };
    EXPECT_NE(errorOf(R"({"material": {"file": "../materials/hips.json"},
                          "heat": {"heaters": [{"name": "p", "power": -5}]}})")
                  .find("heat.heaters[0].power"),
              std::string::npos);
    EXPECT_NE(errorOf(R"({"heat": {}})").find("heat: needs a \"material\""), std::string::npos);
    EXPECT_NE(errorOf(R"({"material": {"file": "../materials/hips.json"}, "sheet": {"stiffness": {"planar": 5}}})")
                  .find("sheet.stiffness: not used with a material"),
              std::string::npos);
    EXPECT_NE(errorOf(R"({"material": {"properties": {"name": "x", "density": 1000, "specific_heat": 1000,
                          "conductivity": -0.2, "glass_transition_c": 100, "upper_c": 200, "glassy_modulus": 2e9,
                          "rubbery_modulus": 1e6, "viscosity_at_transition": 1e14,
                          "forming_window": {"set_c": 80, "lower_c": 120, "normal_c": 140, "upper_c": 160}}}})")
                  .find("conductivity"),
              std::string::npos);
    EXPECT_NE(errorOf(R"({"material": {"file": "../materials/hips.json"}, "heat": {},
                          "script": [{"time": 1, "action": "heater", "heater": "ghost"}]})")
                  .find("script[0].heater: no heater is named 'ghost'"),
              std::string::npos);
}

// A heat scene with the default room (whose walls give no temperature) and an obstacle without "temperature_c"
// loads and runs: both are at the air's temperature, so a cold sheet lying on the obstacle in 60 C air warms.
TEST(FormingScene, ObstaclesAndTheRoomWithoutATemperatureTakeTheAirs)
{
    const std::string json = R"({
      "sheet": { "size": "6x2x6", "min": [-0.1, 0.011, -0.1], "max": [0.1, 0.02, 0.1] },
      "material": { "file": "../materials/pet.json" },
      "heat": { "initial_temperature_c": 20, "air_temperature_c": 60, "air_heat_transfer": 0,
                "contact_heat_transfer": 500 },
      "obstacles": [ { "name": "table", "type": "box", "position": [0, -0.1, 0], "half_extents": [0.3, 0.1, 0.3] } ],
      "integrator": { "type": "implicit" },
      "run": { "duration": 1, "stop_at_rest": false } })";
    std::unique_ptr<Scene> scene;
    ASSERT_EQ(masse::test::inputErrorOf(
                  [&]
                  {
                      scene = std::make_unique<Scene>(
                          parseScene(nlohmann::json::parse(json), source + "/data/scenes", "default-temperatures"));
                  }),
              "");
    while (!scene->finished())
    {
        scene->step();
    }
    const std::vector<Real>& temperature = scene->thermal()->temperature();
    const Real coolest = *std::min_element(temperature.begin(), temperature.end());
    EXPECT_GE(scene->eventTime("contact", "table"), 0.0);
    EXPECT_GT(coolest, celsiusToKelvin(20)); // every mass warmed: the table (or its neighbours) is at 60 C
    const Real warmest = *std::max_element(temperature.begin(), temperature.end());
    EXPECT_LT(warmest, celsiusToKelvin(60) + 1e-9);
}

// The divergence guard's speed bound counts a forming pressure among the causes that move the sheet: the work of the
// strongest pressure over the sheet's size on its areal mass, sqrt(2 p d / (rho h0)), and with air drag at most the
// terminal speed p / (rho h0 c). The vacuum cup's 80 kPa on 2 mm of ABS with a drag of 200/s: the smaller of the two.
// Without it the bound was the fall under gravity through the drag (0.05 m/s), so a wall the vacuum draws onto the
// mould at a few metres a second was stopped as diverged.
TEST(FormingScene, TheGuardCountsTheFormingPressureAmongWhatMovesTheSheet)
{
    const SceneSpec cup = loadScene(source + "/data/scenes/vacuum-forming-cup.json");
    const Real arealMass = cup.material.material.density * cup.material.thickness;
    const Real size = (cup.sheet.lattice.maxCorner - cup.sheet.lattice.minCorner).norm();
    const Real work = std::sqrt(2 * 80000 * size / arealMass);
    const Real terminal = 80000 / (arealMass * cup.environment.airDampingRate);
    EXPECT_NEAR(fastestScriptedSpeed(cup, 1e-3), std::min(work, terminal), 1e-9 * work);
    EXPECT_GT(fastestScriptedSpeed(cup, 1e-3), 100.0) << "tens of metres a second are within the bound";

    SceneSpec still = cup;
    still.forming.pressure = {{0, 0}, {1, 0}};
    EXPECT_LT(fastestScriptedSpeed(still, 1e-3), 0.1) << "without pressure only gravity through the drag remains";
}
