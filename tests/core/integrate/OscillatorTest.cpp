// Oscillation frequencies and damping against closed forms (../shared/reference/physics.md section 5).

#include "support/TestSystems.h"

#include <gtest/gtest.h>

#include <numbers>

using namespace masse;
using namespace masse::test;

namespace
{
const IntegratorKind accurateIntegrators[] = {IntegratorKind::SymplecticEuler, IntegratorKind::VelocityVerlet};
}

// Two free masses on a spring oscillate with period 2 pi sqrt(mu / k), mu = m1 m2 / (m1 + m2). Tolerance 0.5%.
TEST(Oscillator, TwoMassPeriodMatchesReducedMass)
{
    const Real m1 = 1.0;
    const Real m2 = 3.0;
    const Real k = 10.0;
    const Real mu = m1 * m2 / (m1 + m2);
    const Real expected = 2 * std::numbers::pi * std::sqrt(mu / k);
    for (IntegratorKind kind : accurateIntegrators)
    {
        MassSpringSystem system;
        system.particles.add(Vec3(0, 0, 0), m1);
        system.particles.add(Vec3(1.1, 0, 0), m2); // stretched by 0.1
        system.springs.add(0, 1, 1.0, SpringClass::Planar);
        system.springs.mutableStiffness()[0] = k;
        system.forces.gravity.setZero();
        SimulatorSettings settings;
        settings.integrator = kind;
        Simulator simulator(std::move(system), settings);
        UpwardCrossings crossings;
        simulate(simulator, 10 * expected, 1e-3,
                 [&](const Simulator& s)
                 {
                     const Particles& p = s.system().particles;
                     crossings.add(s.time(), (p.position[1] - p.position[0]).norm() - 1.0);
                 });
        ASSERT_GE(crossings.count(), 8u);
        EXPECT_NEAR(crossings.meanPeriod(), expected, 0.005 * expected) << integratorName(kind);
    }
}

// A chain of N masses between two fixed ends (N + 1 springs) has modes omega_n = 2 sqrt(k/m) sin(n pi / (2(N+1))).
// Excite the first three longitudinal mode shapes one at a time and measure each period. Tolerance 1%.
TEST(Oscillator, FixedChainLowestModesMatchAnalyticFrequencies)
{
    const int free = 10;
    const Real m = 0.01;
    const Real k = 50.0;
    const Real spacing = 0.1;
    for (IntegratorKind kind : accurateIntegrators)
    {
        for (int mode = 1; mode <= 3; ++mode)
        {
            MassSpringSystem system = makeChain(free + 2, m, k, spacing);
            system.particles.setPinned(0, true);
            system.particles.setPinned(Index(free + 1), true);
            std::vector<Real> shape(std::size_t(free + 2), 0.0);
            for (int j = 1; j <= free; ++j)
            {
                shape[std::size_t(j)] = std::sin(mode * std::numbers::pi * j / (free + 1));
                system.particles.position[std::size_t(j)].x() += 0.01 * spacing * shape[std::size_t(j)];
            }
            const Real omega = 2 * std::sqrt(k / m) * std::sin(mode * std::numbers::pi / (2 * (free + 1)));
            const Real expected = 2 * std::numbers::pi / omega;

            SimulatorSettings settings;
            settings.integrator = kind;
            Simulator simulator(std::move(system), settings);
            UpwardCrossings crossings;
            simulate(simulator, 10 * expected, expected / 400,
                     [&](const Simulator& s)
                     {
                         Real amplitude = 0;
                         for (int j = 1; j <= free; ++j)
                         {
                             const Real displacement = s.system().particles.position[std::size_t(j)].x() - j * spacing;
                             amplitude += displacement * shape[std::size_t(j)];
                         }
                         crossings.add(s.time(), amplitude);
                     });
            ASSERT_GE(crossings.count(), 8u);
            EXPECT_NEAR(crossings.meanPeriod(), expected, 0.01 * expected) << integratorName(kind) << " mode " << mode;
        }
    }
}

// A mass on a damped spring to a fixed point: successive peaks shrink by the logarithmic decrement
// delta = 2 pi zeta / sqrt(1 - zeta^2), zeta = k_d / (2 sqrt(k m)), i.e. the envelope exp(-zeta omega0 t).
// Tolerance 1% on delta.
TEST(Oscillator, DampedSpringDecaysAlongAnalyticEnvelope)
{
    const Real m = 0.5;
    const Real k = 20.0;
    const Real zeta = 0.05;
    const Real kd = 2 * zeta * std::sqrt(k * m);
    const Real expectedDecrement = 2 * std::numbers::pi * zeta / std::sqrt(1 - zeta * zeta);
    for (IntegratorKind kind : accurateIntegrators)
    {
        MassSpringSystem system = makeChain(2, m, k, 1.0, kd);
        system.particles.setPinned(0, true);
        system.particles.position[1].x() += 0.2;
        SimulatorSettings settings;
        settings.integrator = kind;
        Simulator simulator(std::move(system), settings);

        std::vector<Real> peaks;
        Real before = 0.2;
        Real current = 0.2;
        simulate(simulator, 8.0, 1e-4,
                 [&](const Simulator& s)
                 {
                     const Real next = s.system().particles.position[1].x() - 1.0;
                     if (current > before && current >= next && current > 0)
                     {
                         peaks.push_back(current);
                     }
                     before = current;
                     current = next;
                 });
        ASSERT_GE(peaks.size(), 5u);
        const Real decrement = std::log(peaks.front() / peaks.back()) / Real(peaks.size() - 1);
        EXPECT_NEAR(decrement, expectedDecrement, 0.01 * expectedDecrement) << integratorName(kind);
    }
}
