// Scene files: the shipped scenes load, every bad scene is refused with its key's path, and "extends" merges.

#include "support/TestSystems.h"

#include "scene/Scene.h"
#include "scene/SceneFile.h"
#include "scene/json/FieldKeys.h"

#include "core/InputError.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

using namespace masse;
using namespace masse::scene;

namespace
{
const std::string source = MASSE_SOURCE_DIR;

std::string errorOf(const std::string& file)
{
    return masse::test::inputErrorOf([&] { Scene scene(loadScene(file)); });
}
} // namespace

TEST(SceneFile, EveryShippedSceneLoadsAndBuilds)
{
    int count = 0;
    for (const char* folder : {"/data/scenes", "/data/regression"})
    {
        for (const auto& entry : std::filesystem::directory_iterator(source + folder))
        {
            if (entry.path().extension() == ".json")
            {
                EXPECT_EQ(errorOf(entry.path().string()), "") << entry.path();
                ++count;
            }
        }
    }
    EXPECT_GE(count, 10);
}

// Each bad scene names the file, the key's path and what is wrong.
TEST(SceneFile, BadScenesAreRefusedWithTheKeyPath)
{
    const std::pair<const char*, const char*> cases[] = {
        {"malformed.json", "malformed JSON: parse error at line 2, column 31"},
        {"unknown-key.json", "sheet.stifness: unknown key (did you mean 'stiffness'?)"},
        {"wrong-type.json", "sheet.mass: expected a number (got \"heavy\")"},
        {"size-too-small.json", "sheet.size: expected NxLxN with N >= 2"},
        {"negative-time.json", "script[0].time: must be >= 0 (got -1)"},
        {"missing-obstacle.json", "script[0].obstacle: no obstacle is named 'ghost'"},
        {"degenerate-hull.json", "obstacle 'flat': a hull needs at least 4 points not all in one plane"},
        {"missing-mesh.json", "obstacle 'statue': mesh file"},
        {"negative-radius.json", "contact.radius: must be > 0 (got -0.01)"},
        {"unknown-grab.json", "script[0].grab: no earlier grab is labelled 'hand'"},
        {"negative-dt.json", "integrator.dt: must be in [1e-06, 1] (got -0.03)"},
        {"unknown-structure.json",
         "sheet.structure: unknown value 'hexagon' (expected one of square2d, samm, slamm, trimm)"},
        {"unknown-response.json",
         "contact.response: unknown value 'stiky' (did you mean 'sticky'?) (expected one of sticky, friction, "
         "frictionless)"},
        {"missing-mass.json", "script[0].mass: 5000 is beyond the sheet's 25 masses, 0 to 24 (sheet.size 4x2x4)"},
        {"unknown-top-key.json", "obstacle: unknown key (did you mean 'obstacles'?)"},
        {"bullet-klst.json", "bullet.kLST: must be in (0, 1] (got 1.5)"},
        {"bullet-unknown-key.json", "bullet.kLTS: unknown key (did you mean 'kLST'?)"},
        {"bullet-collisions.json", "bullet.collisions: CL_RS is not supported: cluster collision needs the sheet cut"},
        {"gravity-beyond-range.json", "environment.gravity: 1e+200 m/s^2 is beyond the plausible 1000 m/s^2"},
    };
    for (const auto& [file, expected] : cases)
    {
        const std::string path = source + "/tests/bad-scenes/" + file;
        const std::string message = errorOf(path);
        EXPECT_NE(message.find(path + ": "), std::string::npos) << file << ": " << message;
        EXPECT_NE(message.find(expected), std::string::npos) << file << ": " << message;
    }
}

// The core names a bad value by its own field ("hotAirZones[0].maxCorner"); the scene names the key that gave it. One
// case for each kind of core check a scene file reaches: the message starts with the origin and the key's full path.
TEST(SceneFile, ValuesTheCoreRefusesAreNamedByTheirKey)
{
    const std::string hips = R"("material": {"file": ")" + source + R"(/data/materials/hips.json"})";
    const std::string properties =
        R"("name": "x", "density": 1000, "specific_heat": 1000, "glass_transition_c": 100, "upper_c": 200,
           "glassy_modulus": 2e9, "rubbery_modulus": 1e6, "viscosity_at_transition": 1e14)";
    const std::string window = R"("forming_window": {"set_c": 80, "lower_c": 120, "normal_c": 140, "upper_c": 160})";
    const std::pair<std::string, std::string> cases[] = {
        {R"({"sheet": {"size": "8x8"}})", "sheet.size: expected NxLxN, e.g. 8x2x8 (got '8x8')"},
        {R"({"sheet": {"min": [0, 0, 0], "max": [-1, 1, 1]}})", "sheet.max: must exceed the min corner along x and z"},
        {R"({"sheet": {"min": [0, 0, 0], "max": [1, 0, 1]}})",
         "sheet.max: must exceed the min corner along y for a multi-layer sheet"},
        {"{" + hips + R"(, "heat": {"heaters": [{"name": "a"}, {"name": "b", "power": -5}]}})",
         "heat.heaters[1].power: must be >= 0 W (got -5)"},
        {"{" + hips + R"(, "heat": {"heaters": [{"name": "a", "normal": [0, 1, 0], "width_axis": [0, 2, 0]}]}})",
         "heat.heaters[0].width_axis: must be a direction not parallel to the normal"},
        {"{" + hips + R"(, "heat": {"hot_air_zones": [{"min": [0, 0, 0], "max": [-1, 1, 1]}]}})",
         "heat.hot_air_zones[0].max: must exceed the min corner on every axis"},
        {"{" + hips + R"(, "heat": {"hot_air_zones": [{"heat_transfer": -1}]}})",
         "heat.hot_air_zones[0].heat_transfer: must be >= 0 W/(m^2 K) (got -1)"},
        {R"({"material": {"properties": {)" + properties + R"(, "conductivity": -0.2, )" + window + "}}}",
         "material.properties.conductivity: must be a positive number of W/(m K) (got -0.2)"},
        {R"({"material": {"properties": {)" + properties + R"(, "conductivity": 0.2, "transition_c": 90, )" + window +
             "}}}",
         "material.properties.transition_c: must be at or above the glass transition (got 90 C and 100 C)"},
        {R"({"material": {"properties": {)" + properties + R"(, "conductivity": 0.2, "forming_window": {"set_c": 80,
           "lower_c": 120, "normal_c": 170, "upper_c": 160}}}})",
         "material.properties.forming_window.normal_c: must lie between the lower and the upper forming temperature"},
        {"{" + hips + R"(, "forming": {"pressure": [{"time": 2, "pressure": 1}, {"time": 1, "pressure": 2}]}})",
         "forming.pressure[1].time: the keys must be in increasing time (1 s follows 2 s)"},
    };
    for (const auto& [json, expected] : cases)
    {
        // A named copy: clang 14 refuses a lambda that captures a structured binding.
        const std::string& text = json;
        const std::string message = masse::test::inputErrorOf(
            [&] { Scene scene(parseScene(nlohmann::json::parse(text), source + "/data/scenes", "inline")); });
        EXPECT_EQ(message.rfind("inline: " + expected, 0), 0u) << json << "\n" << message;
    }
}

// The obstacles' and the room's descriptions are the scene layer's own: their bad values are named by key when read,
// before the bridge builds anything.
TEST(SceneFile, ObstacleAndRoomValuesAreNamedByTheirKey)
{
    const std::pair<std::string, std::string> cases[] = {
        {R"({"obstacles": [{"name": "b", "type": "box", "half_extents": [0, 1, 1]}]})",
         "obstacles[0].half_extents: must be positive numbers of metres (got 0, 1, 1)"},
        {R"({"obstacles": [{"name": "a", "half_extents": [1, 1, 1]},
                           {"name": "p", "type": "prism", "width": 1, "height": -2, "length": 1}]})",
         "obstacles[1].height: must be a positive number of metres (got -2)"},
        {R"({"environment": {"room": {"min": [0, 0, 0], "max": [-1, 1, 1]}}})",
         "environment.room.max: must exceed min on every axis"},
        {R"({"environment": {"room": {"wall_thickness": 0}}})", "environment.room.wall_thickness: must be > 0"},
    };
    for (const auto& [json, expected] : cases)
    {
        // A named copy: clang 14 refuses a lambda that captures a structured binding.
        const std::string& text = json;
        const std::string message = masse::test::inputErrorOf(
            [&] { Scene scene(parseScene(nlohmann::json::parse(text), source + "/data/scenes", "inline")); });
        EXPECT_EQ(message.rfind("inline: " + expected, 0), 0u) << json << "\n" << message;
    }
}

// Every key with a unit has a plausible range (data/scenes/README.md, "Plausible ranges"): a unit mistake is refused
// when the file is read, naming the key and the likely mistake, and a number no machine has (a gravity of 1e100 m/s^2,
// a corner at -1e308 m) is refused instead of running to a wrong end.
TEST(SceneFile, ImplausibleValuesAreRefusedNamingTheLikelyMistake)
{
    const std::string pmma = R"("material": {"file": ")" + source + R"(/data/materials/pmma.json"})";
    const std::string properties =
        R"("name": "x", "specific_heat": 1000, "conductivity": 0.2, "glass_transition_c": 100, "upper_c": 200,
           "glassy_modulus": 2e9, "rubbery_modulus": 1e6, "viscosity_at_transition": 1e14,
           "forming_window": {"set_c": 80, "lower_c": 120, "normal_c": 140, "upper_c": 160})";
    const std::string grab = R"({"action": "grab", "mass": 0, "path": [{"time": 0, "position": [0, 1, 0]}])";
    const std::pair<std::string, std::string> cases[] = {
        {R"({"environment": {"gravity": [0, -1e100, 0]}})",
         "environment.gravity: 1e+100 m/s^2 is beyond the plausible 1000 m/s^2 (about 100 g; Earth's is 9.81 m/s^2)"},
        {R"({"environment": {"gravity": [0, -1e308, 0]}})", "environment.gravity: 1e+308 m/s^2 is beyond"},
        {R"({"script": [{"time": 1, "action": "gravity", "value": [0, 0, 5000]}]})",
         "script[0].value: 5000 m/s^2 is beyond the plausible 1000 m/s^2"},
        {R"({"material": {"file": ")" + source + R"(/data/materials/pet.json", "thickness": 3}})",
         "material.thickness: 3 m is outside a sheet's plausible 0.01 mm to 50 mm: did you mean 0.003 (3 mm)?"},
        {"{" + pmma + R"(, "heat": {"initial_temperature_c": 293}})",
         "heat.initial_temperature_c: 293 C is above the material's 205 C upper limit (PMMA's upper_c, where its "
         "model ends); kelvin? 293 K is 19.85 C"},
        {"{" + pmma + R"(, "heat": {"air_temperature_c": 400}})",
         "heat.air_temperature_c: 400 C is above the material's 205 C upper limit (PMMA's upper_c, where its model "
         "ends); kelvin? 400 K is 126.85 C"},
        {"{" + pmma + R"(, "heat": {"air_temperature_c": 500}})",
         "heat.air_temperature_c: 500 C is above the material's 205 C upper limit (PMMA's upper_c, where its model "
         "ends)"},
        {"{" + pmma + R"(, "heat": {}, "obstacles": [{"name": "plug", "half_extents": [1, 1, 1],
           "temperature_c": 900}]})",
         "obstacles[0].temperature_c: 900 C is above the material's 205 C upper limit (PMMA's upper_c, where its model "
         "ends)"},
        {"{" + pmma + R"(, "heat": {"hot_air_zones": [{"temperature_c": 450}]}})",
         "heat.hot_air_zones[0].temperature_c: 450 C is above"},
        {"{" + pmma + R"(, "heat": {}, "script": [{"time": 1, "action": "ambient", "temperature_c": 300}]})",
         "script[0].temperature_c: 300 C is above the material's 205 C upper limit"},
        {R"({"material": {"properties": {)" + properties + R"(, "density": 1.36}}})",
         "material.properties.density: 1.36 kg/m^3 is outside the plausible 10 to 25000 kg/m^3: did you mean 1360 "
         "(1.36 g/cm^3)?"},
        {R"({"sheet": {"min": [-1e308, 0, 0]}})",
         "sheet.min: (-1e+308, 0, 0) m is farther than 1000 m from the origin along an axis"},
        {R"({"environment": {"room": {"max": [1e5, 3, 3]}}})", "environment.room.max: (100000, 3, 3) m is farther"},
        {R"({"obstacles": [{"name": "b", "half_extents": [1, 1, 1], "position": [0, 1e300, 0]}]})",
         "obstacles[0].position: (0, 1e+300, 0) m is farther than 1000 m"},
        {R"({"obstacles": [{"name": "b", "half_extents": [1, 1, 1], "path": [{"time": 0, "position": [0, 0, 0]},
           {"time": 1e-300, "position": [0, 1e300, 0]}]}]})",
         "obstacles[0].path[1].position: (0, 1e+300, 0) m is farther than 1000 m"},
        {R"({"obstacles": [{"name": "b", "half_extents": [1, 5000, 1]}]})",
         "obstacles[0].half_extents: 5000 m is longer than 1000 m"},
        {R"({"script": [)" + grab + R"(, "stiffness": 1e308}]})",
         "script[0].stiffness: must be in (0, 1e+06] N/m (got 1e+308)"},
        {R"({"script": [)" + grab + R"(, "max_force": 1e300}]})", "script[0].max_force: must be in (0, 1e+06] N"},
        {R"({"script": [{"action": "grab", "near": [0, 0, -2e3], "path": [{"time": 0, "position": [0, 1, 0]}]}]})",
         "script[0].near: (0, 0, -2000) m is farther than 1000 m"},
        {R"({"sheet": {"min": [0, 0, 0], "max": [1, 3, 1]}})",
         "sheet.max: the sheet's box is 3 m tall (min y 0 to max y 3), beyond a sheet's plausible 0.5 m: did you mean "
         "a max y of 0.003 (3 mm above min y)?"},
        {R"({"sheet": {"min": [0, -2, 0], "max": [1, 0, 1]}})", "sheet.max: the sheet's box is 2 m tall"},
        {"{" + pmma + R"(, "heat": {"heaters": [{"name": "p", "power": 10, "width": 0.8, "length": 0.8}]}})",
         "heat.heaters[0].power: 10 W from a 0.8 m x 0.8 m panel is 15.625 W/m^2, outside a radiant heater's "
         "plausible 100 to 1e+06 W/m^2: did you mean 10000 (10 kW)?"},
        {"{" + pmma + R"(, "heat": {"heaters": [{"name": "p", "power": 1e9, "on": false}]}})",
         "heat.heaters[0].power: 1e+09 W from a 1 m x 1 m panel is 1e+09 W/m^2, outside a radiant heater's "
         "plausible 100 to 1e+06 W/m^2"},
        {"{" + pmma + R"(, "heat": {"heaters": [{"name": "p", "power": 10000, "width": 800}]}})",
         "heat.heaters[0].width: 800 m is outside a heater panel's plausible 0.01 to 10 m: did you mean 0.8 (800 mm)?"},
        {"{" + pmma + R"(, "heat": {"heaters": [{"name": "p", "length": 0.001}]}})",
         "heat.heaters[0].length: 0.001 m is outside a heater panel's plausible 0.01 to 10 m"},
    };
    for (const auto& [json, expected] : cases)
    {
        const std::string& text = json;
        const std::string message = masse::test::inputErrorOf(
            [&] { Scene scene(parseScene(nlohmann::json::parse(text), source + "/data/scenes", "inline")); });
        EXPECT_EQ(message.rfind("inline: " + expected, 0), 0u) << json << "\n" << message;
    }
}

// The tables' lookup: indices are carried over in order, an entry for one element wins, an unknown field has no key.
TEST(FieldKeys, KeyOfCarriesTheIndicesOver)
{
    EXPECT_EQ(keyOf(thermalKeys, "hotAirZones[12].maxCorner"), "hot_air_zones[12].max");
    EXPECT_EQ(keyOf(thermalKeys, "airHeatTransfer"), "air_heat_transfer");
    EXPECT_EQ(keyOf(sheetKeys, "springClasses[1].stiffness"), "stiffness.inter_layer");
    EXPECT_EQ(keyOf(pressureKeys, "keys[3].pressure"), "pressure[3].pressure");
    EXPECT_EQ(keyOf(thermalKeys, "nothing"), "");
    EXPECT_EQ(messageUnder("heat", thermalKeys, InputError("absorptivity", "must be in [0, 1] (got 2)")),
              "heat.absorptivity: must be in [0, 1] (got 2)");
    EXPECT_EQ(messageUnder("heat", thermalKeys, InputError("unknownField", "is bad")), "heat: unknownField: is bad");
    EXPECT_EQ(messageUnder("", materialKeys, InputError("a message of its own")), "a message of its own");
}

TEST(SceneFile, ExtendsMergesTheBaseScene)
{
    const SceneSpec spec = loadScene(source + "/data/regression/paper-drop-03.json");
    EXPECT_EQ(spec.sheet.lattice.countX, 3);
    EXPECT_EQ(spec.obstacles.size(), 2u);
    EXPECT_EQ(spec.obstacles[0].name, "block");
    EXPECT_EQ(spec.time.integrator, IntegratorKind::SymplecticEuler);
}

// Relative paths (a material file, a mesh) resolve against the file that wrote them, through any depth of "extends":
// a scene in one's own folder extends the shipped drape-forming scene (whose material is "../materials/abs.json",
// relative to data/scenes) and adds a mesh relative to its own folder; a scene one folder deeper extends that one and
// names its own material file relative to itself.
TEST(SceneFile, ExtendsResolvesPathsAgainstTheFileThatWroteThem)
{
    namespace fs = std::filesystem;
    const fs::path mine = fs::path(testing::TempDir()) / "masse-extends-paths";
    fs::remove_all(mine);
    fs::create_directories(mine / "meshes");
    fs::create_directories(mine / "deeper" / "materials");
    fs::copy_file(source + "/data/meshes/pyramid.obj", mine / "meshes" / "mould.obj");
    fs::copy_file(source + "/data/materials/pet.json", mine / "deeper" / "materials" / "mine.json");
    auto write = [](const fs::path& path, const std::string& text)
    {
        std::ofstream out(path);
        out << text;
    };
    write(mine / "scene.json", R"({ "extends": ")" + source + R"(/data/scenes/drape-forming.json",
      "obstacles": [ { "name": "mould", "type": "mesh", "file": "meshes/mould.obj", "scale": 0.2 } ] })");
    write(mine / "deeper" / "level2.json", R"({ "extends": "../scene.json",
      "material": { "file": "materials/mine.json" } })");

    const SceneSpec first = loadScene((mine / "scene.json").string());
    EXPECT_EQ(fs::canonical(first.material.file), fs::canonical(source + "/data/materials/abs.json"));
    ASSERT_EQ(first.obstacles.size(), 1u);
    EXPECT_EQ(fs::canonical(first.obstacles[0].shape.file()), fs::canonical(mine / "meshes" / "mould.obj"));
    EXPECT_EQ(errorOf((mine / "scene.json").string()), "");

    const SceneSpec second = loadScene((mine / "deeper" / "level2.json").string());
    EXPECT_EQ(fs::canonical(second.material.file), fs::canonical(mine / "deeper" / "materials" / "mine.json"));
    EXPECT_EQ(second.material.material.name, "PET");
    ASSERT_EQ(second.obstacles.size(), 1u);
    EXPECT_EQ(fs::canonical(second.obstacles[0].shape.file()), fs::canonical(mine / "meshes" / "mould.obj"));
    EXPECT_EQ(errorOf((mine / "deeper" / "level2.json").string()), "");
    fs::remove_all(mine);
}

// The "bullet" object sets the twin's settings key by key; what is left out stays unset (derived from the sheet when
// the twin is built) or at its default; kLST and calibrate exclude each other; ranges name the key.
TEST(SceneFile, BulletKeysSetTheTwinsSettings)
{
    const nlohmann::json document = nlohmann::json::parse(R"({
      "bullet": { "kLST": 0.5, "kDP": 0.01, "kDF": 0.2, "kCHR": 0.9, "kKHR": 0.8, "margin": 0.02,
                  "piterations": 10, "substeps": 4, "sdf_cell_size": 0.05, "collisions": "SDF_RS" } })");
    const SceneSpec spec = parseScene(document, source, "all-bullet-keys");
    const bridge::SoftBodyTwinSettings& s = spec.bullet.settings;
    EXPECT_EQ(*s.kLST, 0.5);
    EXPECT_EQ(*s.kDP, 0.01);
    EXPECT_EQ(*s.kDF, 0.2);
    EXPECT_EQ(s.kCHR, 0.9);
    EXPECT_EQ(s.kKHR, 0.8);
    EXPECT_EQ(*s.margin, 0.02);
    EXPECT_EQ(s.piterations, 10);
    EXPECT_EQ(s.substeps, 4);
    EXPECT_EQ(s.sdfCellSize, 0.05);
    EXPECT_FALSE(spec.bullet.calibrate);

    const SceneSpec defaults = parseScene(nlohmann::json::object(), source, "no-bullet-keys");
    EXPECT_FALSE(defaults.bullet.settings.kLST.has_value());
    EXPECT_FALSE(defaults.bullet.settings.margin.has_value());
    EXPECT_EQ(defaults.bullet.settings.piterations, 4);
    EXPECT_EQ(defaults.bullet.settings.substeps, 1);
    EXPECT_EQ(defaults.bullet.settings.kKHR, 1.0);

    auto errorOfDocument = [](const char* text)
    {
        try
        {
            parseScene(nlohmann::json::parse(text), source, "doc");
        }
        catch (const InputError& e)
        {
            return std::string(e.what());
        }
        return std::string();
    };
    EXPECT_EQ(errorOfDocument(R"({"bullet": {"kLST": 0.5, "calibrate": true}})"),
              "doc: bullet.calibrate: give either kLST or calibrate: true, not both");
    EXPECT_EQ(errorOfDocument(R"({"bullet": {"kDP": 1}})"), "doc: bullet.kDP: must be in [0, 1) (got 1)");
    EXPECT_EQ(errorOfDocument(R"({"bullet": {"margin": 0}})"), "doc: bullet.margin: must be in (0, 1] (got 0)");
    EXPECT_EQ(errorOfDocument(R"({"bullet": {"substeps": 0}})"), "doc: bullet.substeps: must be in [1, 10000] (got 0)");
    EXPECT_EQ(errorOfDocument(R"({"bullet": {"sdf_cell_size": 2}})"),
              "doc: bullet.sdf_cell_size: must be in [0.001, 1] (got 2)");
    EXPECT_EQ(errorOfDocument(R"({"bullet": {"calibrate": "yes"}})"),
              "doc: bullet.calibrate: expected true or false (got \"yes\")");
    EXPECT_EQ(errorOfDocument(R"({"bullet": {"collisions": "SDF_RDF"}})"),
              "doc: bullet.collisions: SDF_RDF is not supported: it belongs to btDeformableMultiBodyDynamicsWorld, "
              "not to the classic soft body the twin uses; use SDF_RS");
    EXPECT_EQ(errorOfDocument(R"({"bullet": {"collisions": "VF_SS"}})"),
              "doc: bullet.collisions: must be SDF_RS (got 'VF_SS')");
}

// A scene that extends another and gives one item of a named list (a heater, an obstacle) by its name with one key
// changes that key and keeps the item's others, where a plain merge patch would replace the item and put the defaults
// in place of its size and position without a word. The extending file's list still decides which items there are.
TEST(SceneFile, ExtendsMergesANamedListItemOverTheBasesItemOfThatName)
{
    namespace fs = std::filesystem;
    const fs::path mine = fs::path(testing::TempDir()) / "masse-extends-named";
    fs::remove_all(mine);
    fs::create_directories(mine);
    std::ofstream(mine / "hotter.json") << R"({ "extends": ")" + source + R"(/data/scenes/sag.json",
      "heat": { "heaters": [ { "name": "panel", "power": 5000 } ] } })";
    const SceneSpec base = loadScene(source + "/data/scenes/sag.json");
    const SceneSpec hotter = loadScene((mine / "hotter.json").string());
    ASSERT_EQ(base.heat.heaterNames.size(), 1u);
    ASSERT_EQ(hotter.heat.heaterNames.size(), 1u);
    ASSERT_EQ(hotter.heat.heaterNames[0], "panel");
    const RadiantHeater& before = base.heat.settings.heaters[0];
    const RadiantHeater& after = hotter.heat.settings.heaters[0];
    EXPECT_EQ(after.power, 5000);
    EXPECT_NE(before.power, 5000) << "the test changes nothing";
    EXPECT_EQ(after.centre, before.centre);
    EXPECT_EQ(after.width, before.width);
    EXPECT_EQ(after.length, before.length);

    // A new name is a new item, taken as given; the list is the extending file's, in its order.
    std::ofstream(mine / "two.json") << R"({ "extends": ")" + source + R"(/data/scenes/sag.json",
      "heat": { "heaters": [ { "name": "second", "power": 100, "centre": [0, 0.5, 0], "width": 0.2, "length": 0.2 },
                             { "name": "panel" } ] } })";
    const SceneSpec two = loadScene((mine / "two.json").string());
    ASSERT_EQ(two.heat.heaterNames.size(), 2u);
    EXPECT_EQ(two.heat.heaterNames[0], "second");
    EXPECT_EQ(two.heat.settings.heaters[0].width, 0.2);
    EXPECT_EQ(two.heat.heaterNames[1], "panel");
    EXPECT_EQ(two.heat.settings.heaters[1].power, before.power);
    EXPECT_EQ(two.heat.settings.heaters[1].centre, before.centre);
}
