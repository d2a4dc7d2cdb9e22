// The second-order implicit integrators against their closed forms. BDF2: a linear oscillator's amplitude and period
// per step; a tumbling sheet's spin and Coulomb friction inside its solve; the paper's drop scene at the paper's step.
// TR-BDF2: the oscillator figures at w h = 1, an undamped sheet's swing, and its refusal of contact.
//
// Why the amplitude targets are as they are: for x'' = -w^2 x, one BDF2 step multiplies the oscillating mode by the
// root r of (3/2 - i w h) r^2 - 2 r + 1/2 = 0 of larger modulus. At w h = 1 that is |r| = 0.9333 with a phase of
// 0.824 rad per step instead of 1: after ten periods (62.8 steps) BDF2 keeps 1.3% of the amplitude and its period is
// 21% long. No two-level BDF2 can keep 90% there (the trapezoidal rule keeps it all but its period is 7.9% long).
// BDF2 keeps 90% over ten periods up to w h = 0.19, where backward Euler keeps 0.2%; the stiff stretching modes (w h up
// to 9) are damped away as they should be. The tests pin BDF2 to its own closed form at w h = 1, and to the 90% / 5%
// figures at w h = 0.15. TR-BDF2 with the trapezoidal rule over 0.82 of the step keeps 90.2% at w h = 1, its period
// 4.95% long (TrBdf2.cpp says why 0.82): its tests hold it to the 90% / 5% figures at w h = 1.

#include "support/ContactRig.h"
#include "support/TestSystems.h"

#include "core/forces/Energy.h"
#include "scene/PaperExperiment.h"
#include "scene/SceneFile.h"

#include <gtest/gtest.h>

#include <complex>

using namespace masse;
using namespace masse::test;

namespace
{
constexpr Real stepSize = 0.03;
constexpr Real twoPi = 6.283185307179586;

/// Two 1 g masses on a spring along x tuned to w h = wh, stretched by 1 mm and let go: no gravity, no damping.
struct TwoMassOscillator
{
    Real omega;
    Real spacing = 0.1;
    Real stretch = 0.001;
    Simulator simulator;

    TwoMassOscillator(Real wh, IntegratorKind kind) : omega(wh / stepSize), simulator(makeSystem(wh), settingsFor(kind))
    {
    }

    static MassSpringSystem makeSystem(Real wh)
    {
        const Real mass = 0.001;
        const Real omega = wh / stepSize;
        // Relative motion of two equal masses: reduced mass m/2, so w^2 = 2 k / m.
        MassSpringSystem system = makeChain(2, mass, omega * omega * mass / 2, 0.1);
        system.forces.airDamping = 0;
        system.particles.position[1].x() += 0.001;
        return system;
    }
    static SimulatorSettings settingsFor(IntegratorKind kind)
    {
        SimulatorSettings settings;
        settings.integrator = kind;
        settings.implicit.tolerance = 1e-12; // the test is about the integrator, not the solver
        return settings;
    }

    /// The stretch of the spring (m).
    Real displacement() const
    {
        const Particles& p = simulator.system().particles;
        return (p.position[1].x() - p.position[0].x()) - spacing;
    }
    /// sqrt(x^2 + (x'/w)^2): constant for the exact motion.
    Real amplitude() const
    {
        const Particles& p = simulator.system().particles;
        const Real rate = p.velocity[1].x() - p.velocity[0].x();
        return std::hypot(displacement(), rate / omega);
    }
};

/// BDF2's growth factor per step for x'' = -w^2 x: the root of larger modulus (see the file comment).
std::complex<Real> bdf2Root(Real wh)
{
    const std::complex<Real> a(1.5, -wh);
    const std::complex<Real> d = std::sqrt(std::complex<Real>(4) - 2.0 * a);
    return (2.0 + d) / (2.0 * a);
}

/// Runs `periods` analytic periods; returns (final amplitude / initial, measured period / analytic period).
std::pair<Real, Real> runOscillator(Real wh, IntegratorKind kind, int periods)
{
    TwoMassOscillator oscillator(wh, kind);
    const Real initial = oscillator.amplitude();
    UpwardCrossings crossings;
    const int steps = int(std::llround(periods * twoPi / wh));
    for (int i = 0; i < steps; ++i)
    {
        oscillator.simulator.step(stepSize);
        crossings.add(oscillator.simulator.time(), oscillator.displacement());
    }
    EXPECT_GE(crossings.count(), std::size_t(periods / 2));
    return {oscillator.amplitude() / initial, crossings.meanPeriod() / (twoPi / oscillator.omega)};
}
} // namespace

// At w h = 1 BDF2 follows its own closed form: amplitude (1 + w^2 h^2)^(-1/2) |r|^(n-1) (the first step is backward
// Euler's; within 10% for the second root, |r2| = 0.30, which dies out in a few steps) and period 2 pi h / arg r
// (within 1%).
TEST(Bdf2, OscillatorAtOmegaHOneFollowsItsClosedForm)
{
    const int periods = 10;
    const auto [amplitude, period] = runOscillator(1.0, IntegratorKind::Bdf2, periods);
    const std::complex<Real> root = bdf2Root(1.0);
    const Real steps = std::round(periods * twoPi);
    const Real expectedAmplitude = std::sqrt(0.5) * std::pow(std::abs(root), steps - 1);
    const Real expectedPeriod = 1.0 / std::arg(root); // in analytic periods: (2 pi / arg r) h over 2 pi / w
    EXPECT_NEAR(amplitude / expectedAmplitude, 1.0, 0.10);
    EXPECT_NEAR(period / expectedPeriod, 1.0, 0.01);
    // And far above backward Euler's (1 + w^2 h^2)^(-n/2) = 3.5e-10.
    EXPECT_GT(amplitude, 1e6 * std::pow(2.0, -steps / 2));
    std::printf("BDF2 at w h = 1: amplitude %.4g (closed form %.4g), period %.4f (closed form %.4f)\n", amplitude,
                expectedAmplitude, period, expectedPeriod);
}

// At w h = 0.15 BDF2 keeps at least 90% of the amplitude after ten periods, its period within 5%.
TEST(Bdf2, OscillatorKeepsNinetyPercentOverTenPeriodsAtSmallOmegaH)
{
    const auto [amplitude, period] = runOscillator(0.15, IntegratorKind::Bdf2, 10);
    EXPECT_GE(amplitude, 0.90);
    EXPECT_LE(amplitude, 1.0 + 1e-9); // and it never gains
    EXPECT_NEAR(period, 1.0, 0.05);
    // Backward Euler at the same step keeps (1 + 0.0225)^(-209.4) = 1%.
    const auto [eulerAmplitude, eulerPeriod] = runOscillator(0.15, IntegratorKind::ImplicitEuler, 10);
    EXPECT_LT(eulerAmplitude, 0.02);
    std::printf("w h = 0.15, ten periods: BDF2 keeps %.4f (period %.4f), backward Euler %.4g\n", amplitude, period,
                eulerAmplitude);
}

// Backward Euler's amplitude follows (1 + h^2 w^2)^(-n/2) exactly (the mode x w + i x' is divided by 1 + i w h each
// step): within 1% after ten periods at w h = 1, where it is 3.5e-10 of the start.
TEST(Bdf2, BackwardEulerAmplitudeMatchesItsClosedForm)
{
    const int periods = 10;
    const auto [amplitude, period] = runOscillator(1.0, IntegratorKind::ImplicitEuler, periods);
    (void)period;
    const Real steps = std::round(periods * twoPi);
    const Real expected = std::pow(1.0 + 1.0, -steps / 2);
    EXPECT_NEAR(amplitude / expected, 1.0, 0.01);
}

namespace
{
/// TR-BDF2's growth factor per step for x'' = -w^2 x at g = 0.82 (TrBdf2.cpp): the trapezoidal rule over g h, then
/// BDF2 through the step's start, that point and its end.
std::complex<Real> trBdf2Factor(Real wh)
{
    const Real g = 0.82;
    const std::complex<Real> z(0, wh);
    const Real c = (1 - g) * (1 - g) / (g * (2 - g));
    const std::complex<Real> trapezoid = (1.0 + g * z / 2.0) / (1.0 - g * z / 2.0);
    return ((1 + c) * trapezoid - c) / (1.0 - (1 - g) / (2 - g) * z);
}
} // namespace

// The figures at w h = 1: TR-BDF2 keeps at least 90% of the amplitude after ten periods, its period within 5%,
// and follows its closed form (amplitude |R|^n within 1%, period 2 pi h / arg R within 0.5%).
TEST(TrBdf2, OscillatorAtOmegaHOneKeepsNinetyPercentOverTenPeriods)
{
    const int periods = 10;
    const auto [amplitude, period] = runOscillator(1.0, IntegratorKind::TrBdf2, periods);
    const std::complex<Real> factor = trBdf2Factor(1.0);
    const Real steps = std::round(periods * twoPi);
    EXPECT_GE(amplitude, 0.90);
    EXPECT_LE(amplitude, 1.0);
    EXPECT_NEAR(period, 1.0, 0.05);
    EXPECT_NEAR(amplitude / std::pow(std::abs(factor), steps), 1.0, 0.01);
    EXPECT_NEAR(period * std::arg(factor), 1.0, 0.005);
    std::printf("TR-BDF2 at w h = 1: amplitude %.4f (closed form %.4f), period %.4f (closed form %.4f)\n", amplitude,
                std::pow(std::abs(factor), steps), period, 1.0 / std::arg(factor));
}

namespace
{
/// The angular velocity about z of a sheet's masses about their centre: L_z / I_z.
Real spinAboutZ(const Particles& p)
{
    Vec3 centre = Vec3::Zero();
    for (const Vec3& x : p.position)
    {
        centre += x;
    }
    centre /= Real(p.size());
    Real momentum = 0;
    Real inertia = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
    {
        const Vec3 r = p.position[i] - centre;
        momentum += p.mass[i] * r.cross(p.velocity[i]).z();
        inertia += p.mass[i] * (r.x() * r.x() + r.y() * r.y());
    }
    return momentum / inertia;
}

/// A Table 1 8x2x8 sheet (with its dashpots; no gravity, no air) tumbling end over end at `omega` about the z axis
/// through its centre: its spin after `steps` steps of 0.03 s.
Real spinAfter(IntegratorKind kind, Real omega, int steps)
{
    MassSpringSystem sheet = paperSheet(8);
    sheet.forces.gravity = Vec3::Zero();
    sheet.forces.airDamping = 0;
    Particles& p = sheet.particles;
    Vec3 centre = Vec3::Zero();
    for (const Vec3& x : p.position)
    {
        centre += x;
    }
    centre /= Real(p.size());
    for (std::size_t i = 0; i < p.size(); ++i)
    {
        p.velocity[i] = Vec3(0, 0, omega).cross(p.position[i] - centre);
    }
    SimulatorSettings settings;
    settings.integrator = kind;
    Simulator simulator(std::move(sheet), settings);
    for (int step = 0; step < steps; ++step)
    {
        simulator.step(stepSize);
    }
    return spinAboutZ(simulator.system().particles);
}
} // namespace

// A sheet tumbling at 7.8 rad/s (what the drop scene's landing on the block's edge gives it: 0.23 rad a step) keeps
// its spin under BDF2, which solves its nonlinear system by Newton. One linearised step, as BDF2 took before, moves
// every mass along the tangent and its stiff springs take the stretch back out of the rotation: measured, the spin
// fell to 1.45 rad/s in ten steps (backward Euler, still linearised, to 2.0; symplectic Euler keeps 7.7). The spin
// is a rigid motion, free of numerical damping in the exact BDF2 step; what it loses here is the first step's
// (backward Euler's, no history yet) and the sheet's 6% dashpots: 7.34 rad/s are left.
TEST(Bdf2, TumblingSheetKeepsItsSpin)
{
    const Real omega = 7.8;
    const Real bdf2 = spinAfter(IntegratorKind::Bdf2, omega, 10);
    const Real trBdf2 = spinAfter(IntegratorKind::TrBdf2, omega, 10); // Newton in each stage
    const Real euler = spinAfter(IntegratorKind::ImplicitEuler, omega, 10);
    EXPECT_GT(bdf2, 0.9 * omega);
    EXPECT_LE(bdf2, omega * (1 + 1e-9)); // and it never gains
    EXPECT_GT(trBdf2, 0.9 * omega);
    EXPECT_LE(trBdf2, omega * (1 + 1e-9));
    EXPECT_LT(euler, 0.5 * omega) << "backward Euler's single linearised step damps the spin";
    std::printf(
        "tumbling sheet after 10 steps: BDF2 %.3f rad/s, TR-BDF2 %.3f rad/s, backward Euler %.3f rad/s of %.3f\n", bdf2,
        trBdf2, euler, omega);
}

// Friction inside the BDF2 solve stays within Coulomb's law when the pull on a resting mass comes during the step: two
// 1 g masses joined by a 90 N/m spring rest on a floor (mu = 0.3); one slides off at 1 m/s, the other is at rest, so
// its friction damping is sized for the regularisation's 1e-4 m/s slip. Friction may take at most
// mu (m_1 + m_2) g t of the pair's momentum. Before the cap (ImplicitSolve's capFriction) the resting mass held the
// pair with a damping of 29 N s/m.
TEST(Bdf2, FrictionOnARestingMassStaysWithinCoulomb)
{
    ContactRig rig;
    rig.environment.addObstacle(makeBox("floor", Vec3(0, -0.5, 0), Vec3(2, 0.5, 2)));
    ContactSettings settings;
    settings.friction = 0.3;
    MassSpringSystem pair = makeChain(2, 0.001, 90.2, 0.1);
    pair.forces.gravity = Vec3(0, -standardGravity, 0);
    for (Vec3& x : pair.particles.position)
    {
        x.y() = settings.radius; // touching the floor
    }
    pair.particles.velocity[0] = Vec3(-1, 0, 0); // leaving the other, pulling it along through the spring
    for (std::size_t i = 0; i < 2; ++i)
    {
        pair.particles.force[i] = pair.particles.mass[i] * pair.forces.gravity; // pressed in from the first frame
    }
    rig.start(std::move(pair), IntegratorKind::Bdf2, settings);
    const int steps = 5;
    for (int step = 0; step < steps; ++step)
    {
        rig.simulator->step(stepSize);
    }
    const Particles& p = rig.particles();
    const Real momentum = -(p.mass[0] * p.velocity[0].x() + p.mass[1] * p.velocity[1].x());
    const Real coulomb = 0.001 - settings.friction * 0.002 * standardGravity * steps * stepSize;
    EXPECT_GT(momentum, 0.98 * coulomb); // friction took no more than Coulomb allows (2% for the regularisation)
    EXPECT_LT(momentum, 0.001 - 0.5 * (0.001 - coulomb)); // and took at least half of it (measured: two thirds)
    EXPECT_NEAR(p.position[0].y(), settings.radius, 1e-6);
    std::printf("pair sliding on a floor after %d steps: momentum %.4g kg m/s, Coulomb's %.4g\n", steps, momentum,
                coulomb);
}

// An undamped Table 1 sheet (no dashpots, no air) swinging from two corners at the paper's step: BDF2 keeps the total
// energy within 5% after 10 s, where backward Euler loses most of it. The sheet is first let settle, hanging from two
// corners of one edge (damped, as the paper's sheet is), then turned rigidly by 30 degrees about the line through the
// two corners and let go undamped: it swings as a curtain in a draught. 5% is of the swing's energy, the total at
// release less the total at rest (the gravity energy has an arbitrary zero, and the springs' static stretch is not
// part of the motion).
//
// Why released from rest and not flat: released flat, the Table 1 sheet (w h up to about 9 for its 90 N/m springs and
// 1 g masses) puts most of its energy into stretching waves as it falls, which any L-stable step of 0.03 s damps away
// (BDF2 lost 20% of the largest kinetic plus spring energy over 10 s, backward Euler 98%): the test would then measure
// the stretching waves' share, not the swing. Turned from rest, the sheet's stretch barely changes, and what moves is
// the swing (w h about 0.1, where BDF2 keeps 98% of an oscillator's energy over 10 s and backward Euler 4%; see the
// oscillator tests above).
//
// BDF2 does not meet the 5%: measured, it loses 9.6% of the 0.182 J swing over the 10 s (backward Euler 99.7%). That
// is what BDF2's closed form takes from a single mode at w h = 0.16 over 10 s (7.7% at 0.15): the swing itself is too
// fast for BDF2 at this step. TR-BDF2 (TrBdf2.cpp) keeps 99.9% of such a mode in its closed form and lost 3.5% here,
// the rest of it to the stretching the swing sets off; the test holds TR-BDF2 to the 5% and prints BDF2's loss.
TEST(TrBdf2, UndampedSheetSwingingFromTwoCornersKeepsItsEnergy)
{
    Lattice lattice;
    MassSpringSystem sheet = paperSheet(12, &lattice);
    const Index cornerA = lattice.bottomCorners()[0];
    const Index cornerB = lattice.bottomCorners()[1];
    sheet.particles.setPinned(cornerA, true);
    sheet.particles.setPinned(cornerB, true);

    // Settle: the paper's damping, backward Euler, 10 s.
    SimulatorSettings settleSettings;
    settleSettings.integrator = IntegratorKind::ImplicitEuler;
    Simulator settling(sheet, settleSettings);
    simulate(settling, 10.0, stepSize, [](const Simulator&) {});
    const Real settledKinetic = computeEnergy(settling.system()).kinetic;

    // The settled shape, undamped, turned by 30 degrees about the corners' line.
    MassSpringSystem hanging = settling.system();
    hanging.forces.airDamping = 0;
    std::vector<Real>& damping = hanging.springs.mutableDamping();
    std::fill(damping.begin(), damping.end(), Real(0));
    const Real restEnergy = computeEnergy(hanging).total();
    const Vec3 pivot = hanging.particles.position[std::size_t(cornerA)];
    const Vec3 axis = (hanging.particles.position[std::size_t(cornerB)] - pivot).normalized();
    const Eigen::AngleAxis<Real> turn(30.0 * 3.141592653589793 / 180.0, axis);
    for (std::size_t i = 0; i < hanging.particles.position.size(); ++i)
    {
        hanging.particles.position[i] = pivot + turn * (hanging.particles.position[i] - pivot);
        hanging.particles.velocity[i] = Vec3::Zero();
    }
    const Real released = computeEnergy(hanging).total();
    const Real swing = released - restEnergy;
    ASSERT_GT(swing, 0.0);
    ASSERT_LT(settledKinetic, 1e-5 * swing) << "the sheet had not settled";

    auto finalEnergy = [&](IntegratorKind kind, Real& largestKinetic)
    {
        SimulatorSettings settings;
        settings.integrator = kind;
        Simulator simulator(hanging, settings);
        largestKinetic = 0;
        simulate(simulator, 10.0, stepSize,
                 [&](const Simulator& s)
                 { largestKinetic = std::max(largestKinetic, computeEnergy(s.system()).kinetic); });
        return computeEnergy(simulator.system());
    };
    Real largestKinetic = 0;
    const Energy tr = finalEnergy(IntegratorKind::TrBdf2, largestKinetic);
    Real largestKineticBdf2 = 0;
    const Energy bdf2 = finalEnergy(IntegratorKind::Bdf2, largestKineticBdf2);
    Real largestKineticEuler = 0;
    const Energy euler = finalEnergy(IntegratorKind::ImplicitEuler, largestKineticEuler);
    std::printf("sheet swinging undamped for 10 s: swing energy %.4g J; TR-BDF2 loses %.4g J (%.2f%%, largest kinetic "
                "%.4g J), BDF2 %.4g J (%.2f%%), backward Euler %.4g J (%.1f%%)\n",
                swing, released - tr.total(), 100 * (released - tr.total()) / swing, largestKinetic,
                released - bdf2.total(), 100 * (released - bdf2.total()) / swing, released - euler.total(),
                100 * (released - euler.total()) / swing);
    EXPECT_GT(largestKinetic, 0.5 * swing) << "the sheet did not swing";
    EXPECT_NEAR(tr.total(), released, 0.05 * swing);
    EXPECT_LT(bdf2.total(), tr.total()) << "BDF2 should lose more of the swing than TR-BDF2";
    EXPECT_LT(euler.total(), released - 0.5 * swing) << "backward Euler should lose most of the swing here";
}

// The paper's experiment with BDF2 at dt = 0.03 s: for every Table 2 size the sheet touches the block, then the
// wedge, then the floor, then comes to rest (the symplectic reference: wedge at 0.95-0.96 s, floor at 1.01-1.04 s).
//
// What it took, measured with `masse paper --integrator bdf2`: with friction as an uncapped damping every size reached
// the floor first (the block's edge held the sheet instead of tipping it); Newton and the friction cap put 3, 6, 8 and
// 12 in order, but 9x2x9 reached the floor at 1.20 s before the wedge at 1.23 s, and with the solve's springs seeing
// constrained masses where BDF2 places them, 3x2x3 and 9x2x9 never came to rest (the sheet slid along the valley at
// 12 mm/s: the projection moved a mass against the block's side by h times the velocity it took away, where BDF2 moves
// it by 2h/3, and the two never agreed again). With speculative constraints, the contact's impulses kept out of the
// history, and the projection's move of 2h/3, the wedge came at 0.96-1.05 s and the floor at 1.05-1.11 s, in order
// for sizes 3 to 12, 14 and 16. With the reactions scaled to the step (the friction had been 2/3 of Coulomb's), 8x2x8
// reached the wedge and the floor in the same frame, and at dt 0.035 five sizes were out of order: a resting mass the
// sheet lifted was held on the block for the rest of the frame. With resting constraints that pull released: the wedge
// at 0.93-1.02 s and the floor at 1.05-1.11 s, in order for sizes 3 to 12, 14 and 16, at dt 0.02, 0.025, 0.03 and
// 0.035, and without friction.
namespace
{
/// The paper's experiment at dt = 0.03 s with `kind`: every Table 2 size in order, every stage reached.
void expectDropStagesInOrder(IntegratorKind kind)
{
    const std::string source = MASSE_SOURCE_DIR;
    scene::SceneSpec base = scene::loadScene(source + "/data/scenes/paper-drop.json");
    base.time.integrator = kind;
    base.time.dt = 0.03;
    const std::vector<scene::PaperRow> rows = scene::runPaperExperiment(base, scene::paperSizes);
    ASSERT_EQ(rows.size(), 5u);
    for (const scene::PaperRow& row : rows)
    {
        EXPECT_TRUE(row.inOrder) << row.size << "x2x" << row.size;
        for (std::size_t stage = 0; stage < 4; ++stage)
        {
            EXPECT_GE(row.simTime[stage], 0.0) << row.size << "x2x" << row.size << ": " << scene::paperStages[stage];
        }
    }
}
} // namespace

// TR-BDF2 too: its steps with contact are BDF2's (TrBdf2.cpp), its free fall and flight its own.
TEST(Bdf2, PaperDropStagesComeInOrderForAllTable2Sizes)
{
    for (const IntegratorKind kind : {IntegratorKind::Bdf2, IntegratorKind::TrBdf2})
    {
        SCOPED_TRACE(std::string(integratorName(kind)));
        expectDropStagesInOrder(kind);
    }
}
