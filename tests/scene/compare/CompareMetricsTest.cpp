// The comparison metrics on made-up trajectories, checked against figures worked out by hand.

#include "scene/compare/CompareMetrics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

using namespace masse;
using namespace masse::scene;

namespace
{
/// A plate 1 cm thick filling |y| <= 0.005 for |x| <= 1 (unbounded in z), as an analytic obstacle.
constexpr Real plateHalf = 0.005;
constexpr Real plateEdge = 1.0;

bool insidePlate(const Vec3& p)
{
    return std::abs(p.y()) < plateHalf && std::abs(p.x()) < plateEdge;
}

/// Signed distance of a point to the plate (negative inside), exact for a slab with square edges in x-y.
Real plateDistance(const Vec3& p)
{
    const Real qx = std::abs(p.x()) - plateEdge;
    const Real qy = std::abs(p.y()) - plateHalf;
    const Real outside = std::hypot(std::max(qx, Real(0)), std::max(qy, Real(0)));
    return outside + std::min(std::max(qx, qy), Real(0));
}

/// Whether the segment meets the plate: sampled densely (the test's segments are short and the plate is not thin
/// against the sampling step of 1e-5 of the segment).
ObstacleQuery plateQuery()
{
    return {[](const Vec3& a, const Vec3& b)
            {
                for (int k = 0; k <= 100000; ++k)
                {
                    if (insidePlate(a + (b - a) * (Real(k) / 100000)))
                    {
                        return true;
                    }
                }
                return false;
            }};
}

std::vector<Real> plateDistances(const std::vector<Vec3>& x)
{
    std::vector<Real> d;
    for (const Vec3& p : x)
    {
        d.push_back(plateDistance(p));
    }
    return d;
}
} // namespace

// Three masses 0, (3, 4, 0) and (1, 2, 2) m apart: RMS = sqrt((0 + 25 + 9) / 3) = 3.3665 m, max 5 m at mass 1.
TEST(CompareMetrics, PositionDistanceIsRmsAndMaxOfPairs)
{
    const std::vector<Vec3> a = {Vec3(1, 1, 1), Vec3(0, 0, 0), Vec3(-1, 0, 2)};
    const std::vector<Vec3> b = {Vec3(1, 1, 1), Vec3(3, 4, 0), Vec3(0, 2, 4)};
    const PositionDistance d = positionDistance(a, b);
    EXPECT_NEAR(d.rms, std::sqrt(34.0 / 3.0), 1e-15);
    EXPECT_DOUBLE_EQ(d.max, 5.0);
    EXPECT_EQ(d.mass, 1u);
    EXPECT_THROW(positionDistance(a, {Vec3::Zero()}), std::invalid_argument);
}

// Radius 0.01 m. Frame 1 distances {0.02, 0.005, -0.003}: depths {0, 0.005, 0.013}. Frame 2 {0.01, 0.009, 0.5}:
// depths {0, 0.001, 0}. Max 0.013; mean (0.005 + 0.013 + 0.001) / 6 = 0.0031667; over the 3 penetrating samples
// 0.0063333; last frame's max 0.001.
TEST(CompareMetrics, PenetrationStatsFromSignedDistances)
{
    PenetrationStats stats(0.01);
    stats.addFrame({0.02, 0.005, -0.003});
    stats.addFrame({0.01, 0.009, 0.5});
    EXPECT_NEAR(stats.max(), 0.013, 1e-15);
    EXPECT_NEAR(stats.mean(), 0.019 / 6, 1e-15);
    EXPECT_NEAR(stats.meanWhenPenetrating(), 0.019 / 3, 1e-15);
    EXPECT_NEAR(stats.lastFrameMax(), 0.001, 1e-15);
    EXPECT_EQ(stats.samples(), 6u);
    EXPECT_EQ(stats.penetratingSamples(), 3u);
    EXPECT_EQ(stats.frames(), 2u);
    EXPECT_THROW(stats.addFrame({std::nan("")}), std::invalid_argument);
}

// Five masses over a 1 cm plate, three frames each:
//   0 falls through the plate within one frame and ends below it     -> beyond
//   1 falls into the plate and stays inside                           -> inside
//   2 dips into the plate and comes back up                           -> entered, not tunnelled
//   3 goes round the plate's edge (x > 1) from above to below         -> never entered
//   4 rests on top with its sphere touching (centre outside)          -> never entered
// and 5 starts inside (not judged).
TEST(CompareMetrics, TunnelCounterTellsThroughInsideDipAndRound)
{
    const std::vector<std::vector<Vec3>> frames = {
        {Vec3(0, 0.5, 0), Vec3(0.2, 0.02, 0), Vec3(0.4, 0.02, 0), Vec3(1.2, 0.3, 0), Vec3(0.6, 0.01, 0),
         Vec3(0.8, 0, 0)},
        {Vec3(0, -0.4, 0), Vec3(0.2, 0.001, 0), Vec3(0.4, 0.002, 0), Vec3(1.2, 0, 0), Vec3(0.6, 0.0095, 0),
         Vec3(0.8, 0, 0)},
        {Vec3(0, -0.5, 0), Vec3(0.2, 0.0, 0), Vec3(0.4, 0.02, 0), Vec3(1.2, -0.3, 0), Vec3(0.6, 0.0095, 0),
         Vec3(0.8, 0.001, 0)},
    };
    const std::vector<Vec3> start = frames[0];
    TunnelCounter counter(start, plateDistances(start), plateQuery());
    for (std::size_t f = 1; f < frames.size(); ++f)
    {
        counter.addFrame(frames[f], plateDistances(frames[f]));
    }
    const TunnelCount count = counter.count();
    EXPECT_EQ(count.beyond, 1u);
    EXPECT_EQ(count.inside, 1u);
    EXPECT_EQ(count.entered, 3u);
    EXPECT_EQ(count.startedInside, 1u);
    EXPECT_EQ(count.tunnelled(), 2u);
    EXPECT_TRUE(counter.entered(0));
    EXPECT_TRUE(counter.entered(2));
    EXPECT_FALSE(counter.entered(3));
    EXPECT_FALSE(counter.entered(4));
}

// Ten frames of 0.03 s taking 1.5 ms each: 15 ms over 0.3 simulated seconds = 50 ms per simulated second.
TEST(CompareMetrics, WallTimePerSimulatedSecond)
{
    RunRecord run;
    for (int i = 1; i <= 10; ++i)
    {
        run.addFrame(0.03 * i, 1.0 / i, 0.0015);
    }
    EXPECT_NEAR(run.simulatedSeconds(), 0.3, 1e-15);
    EXPECT_NEAR(run.wallMsPerSimulatedSecond(), 50.0, 1e-9);
    EXPECT_EQ(run.kineticEnergy.size(), 10u);
    EXPECT_DOUBLE_EQ(run.kineticEnergy[3], 0.25);
}
