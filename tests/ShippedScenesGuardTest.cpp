// Every shipped scene under the divergence guard's settings for it: a breach in a scene a user starts from would stop
// their first run. A whole-scene test (about two minutes on the shared machine), so it sits in the slow binary.

#include "GuardedRun.h"

#include "scene/Scene.h"
#include "scene/SceneFile.h"

#include "core/DivergenceGuard.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

using namespace masse;

// Every shipped scene runs its first second under the guard's settings for it (the energy account on, weighing the
// energy of motion only for material sheets: see GuardBounds.cpp) without a breach.
TEST(DivergenceGuard, ShippedScenesAreNotStopped)
{
    const std::filesystem::path folder = std::filesystem::path(MASSE_SOURCE_DIR) / "data" / "scenes";
    int scenes = 0;
    for (const auto& entry : std::filesystem::directory_iterator(folder))
    {
        if (entry.path().extension() != ".json")
        {
            continue;
        }
        scene::SceneSpec spec = scene::loadScene(entry.path().string());
        spec.run.duration = std::min(spec.run.duration, Real(1));
        scene::Scene scene(spec);
        EXPECT_TRUE(scene.simulator().guard().settings().checkEnergy) << entry.path();
        EXPECT_EQ(scene.simulator().guard().settings().account,
                  spec.material.enabled ? EnergyAccount::Motion : EnergyAccount::Mechanical)
            << entry.path();
        EXPECT_EQ(test::guardMessageOfRun(scene), "") << entry.path();
        ++scenes;
    }
    EXPECT_GE(scenes, 10);
}
