// The run's rest rule (scene/RestTracker.h), shared by the scene and the comparison's Bullet twins.

#include "scene/RestTracker.h"

#include <gtest/gtest.h>

using namespace masse;
using namespace masse::scene;

// Threshold 1e-5 J, hold 0.5 s, frames of 0.1 s. Low energy from t = 0.3 s: at rest at t = 0.8 s, dated 0.3 s, and
// said once. A frame of high energy in between starts the hold again.
TEST(RestTracker, RestsAfterTheHoldOfLowEnergyAndSaysItOnce)
{
    RestTracker rest(1e-5, 0.5);
    int said = 0;
    for (int frame = 1; frame <= 12; ++frame)
    {
        const Real t = 0.1 * frame;
        const Real energy = frame < 3 ? 1.0 : 1e-6;
        if (rest.update(t, energy, true))
        {
            ++said;
            EXPECT_NEAR(t, 0.8, 1e-12);
            EXPECT_NEAR(rest.since(), 0.3, 1e-12);
        }
    }
    EXPECT_EQ(said, 1);
    EXPECT_TRUE(rest.rested());

    RestTracker interrupted(1e-5, 0.5);
    for (int frame = 1; frame <= 7; ++frame)
    {
        EXPECT_FALSE(interrupted.update(0.1 * frame, frame == 5 ? 1.0 : 1e-6, true)) << frame;
    }
    EXPECT_NEAR(interrupted.since(), 0.6, 1e-12);
    EXPECT_FALSE(interrupted.atRest(0.7));
    EXPECT_TRUE(interrupted.atRest(1.1));
}

// While the run is not ready (its script still moving, an obstacle still to touch), low energy does not count.
TEST(RestTracker, LowEnergyCountsOnlyOnceTheRunIsReady)
{
    RestTracker rest(1e-5, 0.5);
    for (int frame = 1; frame <= 10; ++frame)
    {
        EXPECT_FALSE(rest.update(0.1 * frame, 0.0, false)) << frame;
        EXPECT_LT(rest.since(), 0);
    }
    EXPECT_FALSE(rest.rested());
    EXPECT_FALSE(rest.update(1.1, 0.0, true));
    EXPECT_NEAR(rest.since(), 1.1, 1e-12);
    EXPECT_TRUE(rest.update(1.6, 0.0, true));
}
