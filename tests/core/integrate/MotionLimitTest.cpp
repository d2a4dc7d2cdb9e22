// The motion limit (core/integrate/MotionLimit.h): a frame is split into as many solves as keep each mass's predicted
// motion, (|v| + |v - v before|) dt, within the limit; the first frame, with nothing to predict from, starts at the
// most and is corrected after each of its solves, each next solve at most twice the frame so far; never more than the
// most; the count is the same at any thread count and in any order of the masses; and the Simulator takes the frame in
// that many solves.

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

// The first frame starts at the most solves. After its first, of 10/64 ms, a sheet that stayed at rest may take a next
// solve twice that long: the rest, 630/64 ms, in ceil(63 / 2) = 32. A mass that reached 5 m/s in that first solve
// (32000 m/s^2) would move (5 + 32000 L) L in a next solve of L: 0.284 ms keeps it within 4 mm, so the rest takes
// ceil(9.84 / 0.284) = 35. The second frame is split by the change over the whole first, (5 + 5) m/s: 100 mm, 25
// solves. Once the frame's correction is over, and in later frames, the split is kept as it was (0).
TEST(MotionLimit, TheFirstFrameStartsAtTheMostSolvesAndIsCorrectedAfterEachSolve)
{
    const Real dt = 0.01;
    const Real first = dt / most;
    MassSpringSystem sheet = paperSheet(16);
    MotionLimit still(limit, most);
    EXPECT_EQ(still.solvesFor(sheet, dt), most);
    EXPECT_EQ(still.solvesForRest(sheet, first, dt - first), 32);

    MotionLimit pushed(limit, most);
    EXPECT_EQ(pushed.solvesFor(sheet, dt), most);
    sheet.particles.velocity[37] = Vec3(5, 0, 0);
    EXPECT_EQ(pushed.solvesForRest(sheet, first, dt - first), 35);
    EXPECT_EQ(pushed.solvesFor(sheet, dt), 25);
    EXPECT_EQ(pushed.solvesForRest(sheet, dt / 2, dt / 2), 0) << "a later frame keeps its split";

    MassSpringSystem atRest = paperSheet(16);
    MotionLimit ending(limit, most);
    ending.solvesFor(atRest, dt);
    EXPECT_EQ(ending.solvesForRest(atRest, dt / 2, dt / 2), 1) << "a next solve as long as the frame so far";
    EXPECT_EQ(ending.solvesForRest(atRest, dt / 4, dt / 4), 0) << "the frame's correction ended with the last count";
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

namespace
{
/// Records each solve's length and the farthest any mass moved in it (each solve is a frame of its own).
class SolveRecorder final : public StepHook
{
public:
    StageSet stages() const override { return {StepStage::BeginFrame, StepStage::EndFrame}; }
    void run(StepStage stage, const StageCall& call) override
    {
        const std::vector<Vec3>& x = call.system.particles.position;
        if (stage == StepStage::BeginFrame)
        {
            m_start = x;
            lengths.push_back(call.plan.dt);
            return;
        }
        Real farthest = 0;
        for (std::size_t i = 0; i < x.size(); ++i)
        {
            farthest = std::max(farthest, (x[i] - m_start[i]).norm());
        }
        moves.push_back(farthest);
    }

    std::vector<Real> lengths;
    std::vector<Real> moves;

private:
    std::vector<Vec3> m_start;
};
} // namespace

// The first frame under a load that throws the sheet 2 cm in it (a gravity of 400 m/s^2 on a sheet at rest): its
// solves grow from 1/64 of the frame, none moves a mass further than the limit, and the frame takes far fewer than the
// 64 solves of the first guess; they add up to the frame.
TEST(MotionLimit, TheFirstFrameGrowsItsSolvesWithinTheLimit)
{
    SimulatorSettings settings;
    settings.integrator = IntegratorKind::ImplicitEuler;
    MassSpringSystem sheet = paperSheet(16);
    sheet.forces.gravity = Vec3(0, -400, 0);
    std::fill(sheet.particles.pinned.begin(), sheet.particles.pinned.end(), false);
    Simulator simulator(std::move(sheet), settings);
    MotionLimit motion(limit, most);
    SolveRecorder recorder;
    simulator.addHook(&motion);
    simulator.addHook(&recorder);
    const int solves = simulator.step(0.01).substeps;
    ASSERT_EQ(recorder.lengths.size(), std::size_t(solves));
    EXPECT_LT(solves, most / 4);
    EXPECT_GT(solves, 5);
    EXPECT_EQ(recorder.lengths.front(), 0.01 / most);
    EXPECT_NEAR(std::accumulate(recorder.lengths.begin(), recorder.lengths.end(), Real(0)), 0.01, 1e-15);
    Real soFar = 0;
    for (std::size_t k = 0; k < recorder.lengths.size(); ++k)
    {
        EXPECT_LE(recorder.moves[k], limit) << "solve " << k;
        if (k > 0)
        {
            EXPECT_LE(recorder.lengths[k], 2 * soFar * (1 + 1e-12)) << "solve " << k;
        }
        soFar += recorder.lengths[k];
    }
    EXPECT_GT(*std::max_element(recorder.moves.begin(), recorder.moves.end()), limit / 2)
        << "the solves grow until the limit holds them";
}

// The Simulator takes the frame in the solves asked for: the first frame of 10 ms, a sheet at rest under gravity, in
// solves that grow from 1/64 of the frame, each next at most twice the frame so far (1/64, then the rest in 32, in
// 16, in 5 and in 1: 5 solves); a frame whose fastest mass moves at a steady 2.5 m/s (the same at the start of the
// frame before) in 7.
TEST(MotionLimit, TheSimulatorTakesTheFrameInThatManySolves)
{
    SimulatorSettings settings;
    settings.integrator = IntegratorKind::ImplicitEuler;
    Simulator simulator(paperSheet(16), settings);
    MotionLimit motion(limit, most);
    simulator.addHook(&motion);
    EXPECT_EQ(simulator.step(0.01).substeps, 5);
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
