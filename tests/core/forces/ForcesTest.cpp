// Force terms one at a time: Hooke and damping directions, the compression repulsion, user springs, validation.

#include "support/TestSystems.h"

#include "core/InputError.h"
#include "core/forces/Damping.h"
#include "core/forces/Forces.h"
#include "core/forces/SpringForce.h"

#include <gtest/gtest.h>

using namespace masse;
using namespace masse::test;

namespace
{
std::vector<Vec3> forcesOf(const MassSpringSystem& system)
{
    std::vector<Vec3> force;
    evaluateForces(system, system.particles.position, system.particles.velocity, force);
    return force;
}
} // namespace

// Paper equation 1 with damping: a stretched spring pulls its ends together; a spring whose ends separate is damped
// against the separation; forces are equal and opposite.
TEST(Forces, HookeAndDampingActAlongTheSpring)
{
    MassSpringSystem system = makeChain(2, 1.0, 10.0, 1.0, 2.0);
    system.particles.position[1] = Vec3(1.5, 0, 0); // stretched by 0.5
    std::vector<Vec3> f = forcesOf(system);
    EXPECT_NEAR(f[0].x(), 5.0, 1e-12); // k (|d| - s) = 10 * 0.5, toward mass 1
    EXPECT_NEAR(f[1].x(), -5.0, 1e-12);
    EXPECT_NEAR(f[0].y(), 0.0, 1e-12);

    system.particles.position[1] = Vec3(1.0, 0, 0);
    system.particles.velocity[1] = Vec3(3.0, 4.0, 0); // separating at 3 m/s along the spring
    f = forcesOf(system);
    EXPECT_NEAR(f[1].x(), -6.0, 1e-12); // k_d * 3, only the component along the spring
    EXPECT_NEAR(f[1].y(), 0.0, 1e-12);
    EXPECT_NEAR(f[0].x(), 6.0, 1e-12);
}

// The paper prints f = -k_r d/|d|^3; we apply k_r (1/|d|^2 - 1/s^2) along d: it pushes the two masses apart, only
// below the rest length, and fades to zero at it.
TEST(Forces, CompressionRepulsionPushesApart)
{
    MassSpringSystem system = makeChain(2, 1.0, 0.0, 1.0);
    system.forces.repulsion = 1.0;
    system.particles.position[1] = Vec3(0.5, 0, 0);
    std::vector<Vec3> f = forcesOf(system);
    EXPECT_NEAR(f[1].x(), 1.0 * (1 / 0.25 - 1.0), 1e-12); // mass 1, on the +x side, pushed to +x
    EXPECT_NEAR(f[0].x(), -3.0, 1e-12);

    system.particles.position[1] = Vec3(1.0 - 1e-9, 0, 0);
    EXPECT_NEAR(forcesOf(system)[1].x(), 0.0, 1e-8); // continuous at the rest length
    system.particles.position[1] = Vec3(1.5, 0, 0);
    EXPECT_EQ(forcesOf(system)[1].x(), 0.0); // no pull when stretched

    // Dynamics agree: released compressed, the pair moves apart.
    system.particles.position[1] = Vec3(0.5, 0, 0);
    Simulator simulator(std::move(system), SimulatorSettings{});
    simulator.step(0.01);
    const Particles& p = simulator.system().particles;
    EXPECT_GT((p.position[1] - p.position[0]).norm(), 0.5);
    EXPECT_GT(p.velocity[1].x(), 0.0);
    EXPECT_LT(p.velocity[0].x(), 0.0);
}

TEST(Forces, RepulsionPotentialIsTheIntegralOfItsForce)
{
    const Real rest = 1.0;
    const Real kr = 0.7;
    for (Real length : {0.3, 0.6, 0.9})
    {
        const Real h = 1e-6;
        const Real derivative =
            (springPotential(length + h, 0, rest, kr) - springPotential(length - h, 0, rest, kr)) / (2 * h);
        EXPECT_NEAR(-derivative, springForceMagnitude(length, 0, 0, 0, rest, kr), 1e-6);
    }
}

// The paper's dynamic spring: it pulls its mass toward the target, capped at maxForce, and goes away when removed.
TEST(Forces, UserSpringPullsItsMassTowardTheTarget)
{
    MassSpringSystem system;
    system.particles.add(Vec3(0, 0, 0), 0.01);
    system.forces.gravity.setZero();
    UserSpring spring;
    spring.mass = 0;
    spring.target = Vec3(1, 2, 2); // 3 m away
    spring.stiffness = 10.0;
    spring.damping = 0.1;
    const UserSpringId id = system.userSprings.add(spring);
    EXPECT_NEAR(forcesOf(system)[0].norm(), 30.0, 1e-12);
    EXPECT_NEAR(forcesOf(system)[0].normalized().dot(Vec3(1, 2, 2) / 3), 1.0, 1e-12);

    system.userSprings.find(id)->maxForce = 2.0;
    EXPECT_NEAR(forcesOf(system)[0].norm(), 2.0, 1e-12);

    for (IntegratorKind kind : {IntegratorKind::SymplecticEuler, IntegratorKind::ImplicitEuler})
    {
        SimulatorSettings settings;
        settings.integrator = kind;
        Simulator simulator(system, settings);
        // Capped at 2 N, the 10 g mass accelerates at 200 m/s^2: 1 m in the first 0.1 s, still short of the target.
        Real previous = 3.0;
        for (int i = 0; i < 10; ++i)
        {
            simulator.step(0.01);
            const Real distance = (simulator.system().particles.position[0] - spring.target).norm();
            EXPECT_LT(distance, previous) << integratorName(kind);
            previous = distance;
        }
        // Analytic distance 2 m; first-order integrators are off by up to a dt t / 2 = 0.1 m.
        EXPECT_NEAR(previous, 2.0, 0.1 + 1e-9) << integratorName(kind);
    }

    EXPECT_TRUE(system.userSprings.remove(id));
    EXPECT_FALSE(system.userSprings.remove(id));
    EXPECT_EQ(forcesOf(system)[0], Vec3::Zero());
}

// Air damping "0.97 (3%)": over one paper step of 0.03 s a free mass keeps 97% of its velocity, whatever the step.
TEST(Forces, AirDampingKeepsPaperFractionPerPaperStep)
{
    for (IntegratorKind kind : {IntegratorKind::SymplecticEuler, IntegratorKind::ImplicitEuler})
    {
        MassSpringSystem system;
        system.particles.add(Vec3(0, 0, 0), 0.001);
        system.particles.velocity[0] = Vec3(1, 0, 0);
        system.forces.gravity.setZero();
        system.forces.airDamping = airDampingRate(0.97, 0.03);
        SimulatorSettings settings;
        settings.integrator = kind;
        Simulator simulator(std::move(system), settings);
        for (int i = 0; i < 300; ++i)
        {
            simulator.step(1e-4);
        }
        // First-order integrators approximate exp(-c t) to O(c dt): tolerance 1e-4 relative.
        EXPECT_NEAR(simulator.system().particles.velocity[0].x(), 0.97, 0.97 * 1e-4) << integratorName(kind);
    }
}

TEST(Forces, BadSheetParametersAreRefused)
{
    LatticeSpec spec;
    spec.countX = 3;
    spec.countZ = 3;
    const Lattice lattice = buildLattice(spec);
    SheetParams params;
    params.massPerMass = 0;
    EXPECT_THROW(makeSheet(lattice, params), InputError);
    params = SheetParams{};
    params.springClasses[1].stiffness = -5;
    try
    {
        makeSheet(lattice, params);
        ADD_FAILURE() << "negative stiffness accepted";
    }
    catch (const InputError& e)
    {
        EXPECT_NE(std::string(e.what()).find("springClasses[1].stiffness: must be a positive number of N/m (got -5)"),
                  std::string::npos)
            << e.what();
    }
}

// Only bits that are +0 count as no external force: adding -0 to a -0 sum keeps it -0, adding +0 makes it +0, so the
// symplectic pass may skip the array only when every component is +0.
TEST(Forces, NoExternalForcesMeansEveryBitZero)
{
    MassSpringSystem system = paperSheet(4);
    EXPECT_TRUE(noExternalForces(system.particles));
    system.particles.externalForce[7].y() = -0.0;
    EXPECT_FALSE(noExternalForces(system.particles));
    system.particles.externalForce[7].y() = 0.0;
    system.particles.externalForce.back().z() = 1e-300;
    EXPECT_FALSE(noExternalForces(system.particles));
}

// The symplectic pass that skips the external forces gives the bits of the one that adds them when they are all +0,
// on a lattice sheet (its banded kernel): forces, velocities and positions after five substeps, with gravity and with
// a gravity of -0 (a mass at rest then has an own force of -0 before its springs' are added).
TEST(Forces, SymplecticSubstepWithoutExternalForcesHasTheSameBits)
{
    for (const Vec3& gravity : {Vec3(0, -standardGravity, 0), Vec3(-0.0, -0.0, -0.0)})
    {
        MassSpringSystem sheet = paperSheet(12);
        sheet.forces.gravity = gravity;
        ASSERT_NE(sheet.springs.rowPlan(sheet.massCount()), nullptr);
        for (std::size_t i = 0; i < sheet.massCount(); i += 3)
        {
            sheet.particles.velocity[i] = Vec3(0.01 * Real(i % 7), -0.02, i % 2 ? -0.0 : 0.0);
        }
        MassSpringSystem reading = sheet;
        MassSpringSystem skipping = sheet;
        for (int substep = 0; substep < 5; ++substep)
        {
            ASSERT_TRUE(symplecticSubstep(reading, 1e-3, true));
            ASSERT_TRUE(symplecticSubstep(skipping, 1e-3, false));
        }
        EXPECT_TRUE(sameBits(skipping.particles.position, reading.particles.position));
        EXPECT_TRUE(sameBits(skipping.particles.velocity, reading.particles.velocity));
        EXPECT_TRUE(sameBits(skipping.particles.force, reading.particles.force));
    }
}

namespace
{
/// Pushes mass 0 along x from the end of the frame's first substep on.
class PushAfterFirstSubstep final : public StepHook
{
public:
    void afterSubstep(MassSpringSystem& system, StepContext& /*context*/, Real /*h*/, Real /*time*/) override
    {
        system.particles.externalForce[0] = Vec3(1e-3, 0, 0);
    }
    bool writesExternalForcesMidFrame() const override { return true; }
};
} // namespace

// A hook that applies an external force after a substep, and says so, is felt from the next substep on, though the
// frame began with none (the Simulator looks again after such hooks): the frame has the bits of substeps by hand.
TEST(Forces, ExternalForceAHookAppliesMidFrameIsFelt)
{
    MassSpringSystem sheet = paperSheet(8);
    SimulatorSettings settings;
    settings.integrator = IntegratorKind::SymplecticEuler;
    Simulator simulator(sheet, settings);
    PushAfterFirstSubstep push;
    simulator.addHook(&push);
    const StepReport report = simulator.step(paperTimeStep);
    ASSERT_GE(report.substeps, 2);

    MassSpringSystem byHand = sheet;
    for (int substep = 0; substep < report.substeps; ++substep)
    {
        ASSERT_TRUE(symplecticSubstep(byHand, report.substep, true));
        byHand.particles.externalForce[0] = Vec3(1e-3, 0, 0);
    }
    EXPECT_TRUE(sameBits(simulator.system().particles.position, byHand.particles.position));
    // And the push moved the sheet: without it, the same substeps give other bits.
    MassSpringSystem unpushed = sheet;
    for (int substep = 0; substep < report.substeps; ++substep)
    {
        ASSERT_TRUE(symplecticSubstep(unpushed, report.substep, true));
    }
    EXPECT_FALSE(sameBits(simulator.system().particles.position, unpushed.particles.position));
}

// The symplectic pass that stores no forces moves the sheet with the bits of the one that does, and leaves
// particles.force as it found it (what it saves is that store).
TEST(Forces, SymplecticSubstepWithoutStoringForcesMovesTheSame)
{
    MassSpringSystem sheet = paperSheet(12);
    ASSERT_NE(sheet.springs.rowPlan(sheet.massCount()), nullptr);
    for (std::size_t i = 0; i < sheet.massCount(); i += 5)
    {
        sheet.particles.velocity[i] = Vec3(0.01 * Real(i % 3), -0.02, 0.005);
    }
    MassSpringSystem storing = sheet;
    MassSpringSystem skipping = sheet;
    skipping.particles.force.assign(skipping.massCount(), Vec3(7, 8, 9));
    for (int substep = 0; substep < 4; ++substep)
    {
        ASSERT_TRUE(symplecticSubstep(storing, 1e-3, false, true));
        ASSERT_TRUE(symplecticSubstep(skipping, 1e-3, false, false));
    }
    EXPECT_TRUE(sameBits(skipping.particles.position, storing.particles.position));
    EXPECT_TRUE(sameBits(skipping.particles.velocity, storing.particles.velocity));
    EXPECT_TRUE(sameBits(skipping.particles.force, std::vector<Vec3>(skipping.massCount(), Vec3(7, 8, 9))));
}

namespace
{
/// Copies particles.force after every substep; says it reads them or not.
class ForceWatcher final : public StepHook
{
public:
    explicit ForceWatcher(bool reads) : m_reads(reads) {}
    void afterSubstep(MassSpringSystem& system, StepContext& /*context*/, Real /*h*/, Real /*time*/) override
    {
        seen.push_back(system.particles.force);
    }
    bool readsForcesMidFrame() const override { return m_reads; }
    std::vector<std::vector<Vec3>> seen;

private:
    bool m_reads;
};
} // namespace

// A frame stores the forces of its last substep, so what the contact's reach and the guard read between frames does
// not depend on who read them within it; a hook that says it reads them finds each substep's own, and one that does
// not may find an earlier substep's (the first substeps of a frame store none).
TEST(Forces, AFrameEndsWithItsLastSubstepsForcesWhoeverReadsThem)
{
    MassSpringSystem sheet = paperSheet(8);
    SimulatorSettings settings;
    settings.integrator = IntegratorKind::SymplecticEuler;
    Simulator reading(sheet, settings);
    Simulator notReading(sheet, settings);
    ForceWatcher reader(true);
    ForceWatcher other(false);
    reading.addHook(&reader);
    notReading.addHook(&other);
    for (int frame = 0; frame < 2; ++frame)
    {
        const StepReport report = reading.step(paperTimeStep);
        ASSERT_GE(report.substeps, 3);
        notReading.step(paperTimeStep);
    }
    EXPECT_TRUE(sameBits(notReading.system().particles.force, reading.system().particles.force));
    EXPECT_TRUE(sameBits(notReading.system().particles.position, reading.system().particles.position));
    EXPECT_TRUE(sameBits(notReading.system().particles.velocity, reading.system().particles.velocity));
    ASSERT_EQ(reader.seen.size(), other.seen.size());
    const std::size_t perFrame = reader.seen.size() / 2;
    // Each substep's forces are its own for the reader (the sheet speeds up as it falls: its drag changes)...
    for (std::size_t k = 1; k < reader.seen.size(); ++k)
    {
        EXPECT_FALSE(sameBits(reader.seen[k], reader.seen[k - 1])) << "substep " << k;
    }
    // ...while the other finds the previous frame's last ones until its own frame's last substep.
    EXPECT_TRUE(sameBits(other.seen[perFrame], other.seen[perFrame - 1]));
    EXPECT_TRUE(sameBits(other.seen[2 * perFrame - 1], reader.seen[2 * perFrame - 1]));
}
