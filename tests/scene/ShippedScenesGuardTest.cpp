// Every shipped scene under the divergence guard's settings for it: a breach in a scene a user starts from would stop
// their first run. A whole-scene test (about two minutes on the shared machine), so it sits in the slow binary.

#include "support/GuardedRun.h"
#include "support/Sanitizers.h"

#include "scene/Scene.h"
#include "scene/SceneFile.h"

#include "core/DivergenceGuard.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <string>

using namespace masse;

namespace
{
// How much of each scene runs. Under the address sanitizer the first 0.2 s (7 to 10 steps, the forming scenes' first
// factorisation included) is enough to find a bad read or write, and the whole second took 490 s there (the two
// 256x2x256 bench scenes and the three forming scenes, some 28 s in Release), the suite's longest test by far.
constexpr Real firstSeconds = test::underAddressSanitizer ? 0.2 : 1;
} // namespace

// Every shipped scene runs its first second (0.2 s under the address sanitizer) under the guard's settings for it (the
// energy account on, weighing the energy of motion only for material sheets: see GuardBounds.cpp) without a breach.
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
        spec.run.duration = std::min(spec.run.duration, firstSeconds);
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
