// The motion limit (core/integrate/MotionLimit.h): a frame is split into as many solves as keep each mass's predicted
// motion, (|v| + |v - v before|) dt, within the limit; the first frame, with nothing to predict from, into the most;
// never more than the most; the count is the same at any thread count and in any order of the masses; and the
// Simulator takes the frame in that many solves.

#include "support/TestSystems.h"
#include "support/TestThreads.h"

#include "core/Simulator.h"
#include "core/integrate/MotionLimit.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

using namespace masse;
using masse::test::paperSheet;

namespace
{
constexpr Real limit = 0.004; // m a solve
constexpr int most = 64;

/// A 16x2x16 sheet at rest but for mass `fast`, moving at `speed` along x.
MassSpringSystem sheetWithOneFastMass(Index fast, Real speed)
{
    MassSpringSystem sheet = paperSheet(16);
    sheet.particles.velocity[fast] = Vec3(speed, 0, 0);
    return sheet;
}
} // namespace

TEST(MotionLimit, TheFirstFrameIsTakenInTheMostSolves)
{
    MassSpringSystem sheet = paperSheet(16);
    MotionLimit motion(limit, most);
    EXPECT_EQ(motion.solvesFor(sheet, 0.01), most);
    EXPECT_EQ(motion.solvesFor(sheet, 0.01), 1) << "a sheet at rest needs one solve once it has been seen";
}

// At a steady 2.5 m/s a mass moves 25 mm in a frame of 10 ms: ceil(25 / 4) = 7 solves. The same mass gaining 1 m/s
// over the frame before is predicted at (1 + 1) m/s: 20 mm, 5 solves.
TEST(MotionLimit, SplitsAFrameByItsFastestMass)
{
    const Real dt = 0.01;
    MassSpringSystem sheet = sheetWithOneFastMass(37, 2.5);
    MotionLimit steady(limit, most);
    steady.solvesFor(sheet, dt);
    EXPECT_EQ(steady.solvesFor(sheet, dt), 7);
    EXPECT_NEAR(steady.predictedMotion(), 0.025, 1e-15);

    MassSpringSystem rest = paperSheet(16);
    MassSpringSystem speeding = sheetWithOneFastMass(37, 1.0);
    MotionLimit accelerating(limit, most);
    accelerating.solvesFor(rest, dt);
    EXPECT_EQ(accelerating.solvesFor(speeding, dt), 5);
    EXPECT_NEAR(accelerating.predictedMotion(), 0.02, 1e-15);

    MassSpringSystem slow = sheetWithOneFastMass(37, 0.3); // 3 mm: one solve
    MotionLimit calm(limit, most);
    calm.solvesFor(slow, dt);
    EXPECT_EQ(calm.solvesFor(slow, dt), 1);
}

TEST(MotionLimit, NeverSplitsIntoMoreThanTheMost)
{
    MassSpringSystem sheet = sheetWithOneFastMass(3, 1e6);
    MotionLimit motion(limit, most);
    motion.solvesFor(sheet, 0.01);
    EXPECT_EQ(motion.solvesFor(sheet, 0.01), most);
    sheet.particles.velocity[3].x() = std::numeric_limits<Real>::infinity();
    EXPECT_EQ(motion.solvesFor(sheet, 0.01), most) << "a non-finite speed is the guard's to name";
}

// The fastest mass decides wherever it sits and on any number of threads: random speeds, then the same speeds
// shuffled over the masses, at 1, 2 and 3 threads.
TEST(MotionLimit, TheCountDependsOnNeitherTheThreadsNorTheOrderOfTheMasses)
{
    MassSpringSystem sheet = paperSheet(64);
    std::mt19937 random(7);
    std::uniform_real_distribution<Real> speed(-1.2, 1.2);
    for (Vec3& v : sheet.particles.velocity)
    {
        v = Vec3(speed(random), speed(random), speed(random));
    }
    std::vector<int> counts;
    std::vector<Real> motions;
    for (int threads : {1, 2, 3})
    {
        for (bool shuffled : {false, true})
        {
            MassSpringSystem s = sheet;
            if (shuffled)
            {
                std::shuffle(s.particles.velocity.begin(), s.particles.velocity.end(), random);
            }
            const test::BoundPool pool(threads);
            MotionLimit motion(limit, most);
            MassSpringSystem atRest = paperSheet(64);
            motion.solvesFor(atRest, 0.01);
            counts.push_back(motion.solvesFor(s, 0.01));
            motions.push_back(motion.predictedMotion());
        }
    }
    EXPECT_GT(counts.front(), 1);
    for (std::size_t k = 1; k < counts.size(); ++k)
    {
        EXPECT_EQ(counts[k], counts.front()) << k;
        EXPECT_EQ(motions[k], motions.front()) << k;
    }
}

// The Simulator takes the frame in the solves asked for: the first frame of 10 ms in 64; a frame whose fastest mass
// moves at a steady 2.5 m/s (the same at the start of the frame before) in 7.
TEST(MotionLimit, TheSimulatorTakesTheFrameInThatManySolves)
{
    SimulatorSettings settings;
    settings.integrator = IntegratorKind::ImplicitEuler;
    Simulator simulator(paperSheet(16), settings);
    MotionLimit motion(limit, most);
    simulator.addHook(&motion);
    EXPECT_EQ(simulator.step(0.01).substeps, most);
    std::vector<Vec3>& velocity = simulator.system().particles.velocity;
    const auto oneFastMass = [&]
    {
        std::fill(velocity.begin(), velocity.end(), Vec3::Zero());
        velocity[40] = Vec3(2.5, 0, 0);
    };
    oneFastMass();
    simulator.step(0.01);
    oneFastMass();
    EXPECT_EQ(simulator.step(0.01).substeps, 7);
}
