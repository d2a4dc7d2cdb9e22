// Scene files: the shipped scenes load, every bad scene is refused with its key's path, and "extends" merges.

#include "scene/SceneFile.h"
#include "scene/Scene.h"

#include "core/InputError.h"

#include <gtest/gtest.h>

#include <filesystem>

using namespace masse;
using namespace masse::scene;

namespace
{
const std::string source = MASSE_SOURCE_DIR;

std::string errorOf(const std::string& file)
{
    try
    {
        Scene scene(loadScene(file));
    }
    catch (const InputError& e)
    {
        return e.what();
    }
    return "";
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
        {"negative-dt.json", "integrator.dt: must be > 0 (got -0.03)"},
        {"unknown-structure.json",
         "sheet.structure: unknown value 'hexagon' (expected one of square2d, samm, slamm, trimm)"},
        {"missing-mass.json", "script[0].mass: mass 5000 does not exist (the sheet has 25 masses)"},
        {"unknown-top-key.json", "obstacle: unknown key (did you mean 'obstacles'?)"},
    };
    for (const auto& [file, expected] : cases)
    {
        const std::string path = source + "/tests/bad-scenes/" + file;
        const std::string message = errorOf(path);
        EXPECT_NE(message.find(path + ": "), std::string::npos) << file << ": " << message;
        EXPECT_NE(message.find(expected), std::string::npos) << file << ": " << message;
    }
}

TEST(SceneFile, ExtendsMergesTheBaseScene)
{
    const SceneSpec spec = loadScene(source + "/data/regression/paper-drop-03.json");
    EXPECT_EQ(spec.sheet.lattice.countX, 3);
    EXPECT_EQ(spec.obstacles.size(), 2u);
    EXPECT_EQ(spec.obstacles[0].name, "block");
    EXPECT_EQ(spec.time.integrator, IntegratorKind::SymplecticEuler);
}
