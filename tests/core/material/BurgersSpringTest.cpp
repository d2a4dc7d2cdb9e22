// One Burgers spring (Maxwell + Kelvin-Voigt in series) against the closed forms of physics.md section 2: creep,
// recovery and relaxation, the trapezoidal update's dt^2 convergence, the exponential Kelvin update for long steps,
// and the same creep through the Simulator with the ViscoelasticSprings hook.

#include "support/TestSystems.h"

#include "core/material/BurgersSpring.h"
#include "core/material/ViscoelasticSprings.h"
#include "core/material/WlfLaw.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>

using namespace masse;
using namespace masse::test;

namespace
{
/// physics.md's check run: k_K = 2, c_K = 5, k_M = 10, c_M = 40 (N/m and N s/m; a spring of unit length and
/// cross-section, so stress and strain are force and extension).
BurgersParams checkRun()
{
    return BurgersParams{10.0, 40.0, 2.0, 5.0};
}

/// eps(t) = sigma0 [1/E_M + t/eta_M + (1/E_K)(1 - exp(-E_K t/eta_K))]
Real creepExtension(const BurgersParams& p, Real force, Real t)
{
    return force * (1 / p.maxwellStiffness + t / p.maxwellDamping +
                    (1 - std::exp(-p.kelvinStiffness * t / p.kelvinDamping)) / p.kelvinStiffness);
}

/// After unloading at t1: eps(t) = sigma0 t1/eta_M + (sigma0/E_K)(1 - exp(-E_K t1/eta_K)) exp(-E_K (t-t1)/eta_K)
Real recoveryExtension(const BurgersParams& p, Real force, Real t1, Real t)
{
    const Real rate = p.kelvinStiffness / p.kelvinDamping;
    return force * t1 / p.maxwellDamping +
           force / p.kelvinStiffness * (1 - std::exp(-rate * t1)) * std::exp(-rate * (t - t1));
}

/// sigma(t) = eps0 [(q1 - q2 r1) e^(-r1 t) - (q1 - q2 r2) e^(-r2 t)] / sqrt(p1^2 - 4 p2)
Real relaxationForce(const BurgersParams& p, Real extension, Real t)
{
    const Real em = p.maxwellStiffness, etaM = p.maxwellDamping, ek = p.kelvinStiffness, etaK = p.kelvinDamping;
    const Real p1 = etaM / em + etaM / ek + etaK / ek;
    const Real p2 = etaM * etaK / (em * ek);
    const Real q1 = etaM;
    const Real q2 = etaM * etaK / ek;
    const Real root = std::sqrt(p1 * p1 - 4 * p2);
    const Real r1 = (p1 - root) / (2 * p2);
    const Real r2 = (p1 + root) / (2 * p2);
    return extension * ((q1 - q2 * r1) * std::exp(-r1 * t) - (q1 - q2 * r2) * std::exp(-r2 * t)) / root;
}

/// Applies a force step at t = 0 (a step of length 0: the instantaneous elastic response) and holds it for
/// `duration`; returns the largest error of the extension against the closed form, relative to the closed form.
Real creepError(const BurgersParams& p, Real force, Real duration, Real dt)
{
    BurgersState state;
    const BurgersStep jump = burgersStep(p, 0);
    burgersAdvance(jump, state, force, burgersExtension(jump, state, force));
    const BurgersStep step = burgersStep(p, dt);
    Real worst = std::abs(state.extension - creepExtension(p, force, 0)) / creepExtension(p, force, 0);
    const int steps = int(std::llround(duration / dt));
    for (int i = 1; i <= steps; ++i)
    {
        burgersAdvance(step, state, force, burgersExtension(step, state, force));
        const Real expected = creepExtension(p, force, i * dt);
        worst = std::max(worst, std::abs(state.extension - expected) / expected);
    }
    return worst;
}
} // namespace

// Creep under a constant force: the extension follows the closed form within 0.5% at every step (dt = 0.01 s over
// 20 s, five Kelvin retardation times and five Maxwell times).
TEST(BurgersSpring, CreepMatchesClosedForm)
{
    const Real error = creepError(checkRun(), 1.0, 20.0, 0.01);
    EXPECT_LT(error, 0.005);
    RecordProperty("creep_relative_error", std::to_string(error));
}

// The trapezoidal update is second order: halving dt divides the creep error by 4 (accepted 3.5 to 4.5).
TEST(BurgersSpring, CreepErrorFallsAsDtSquared)
{
    const Real coarse = creepError(checkRun(), 1.0, 20.0, 0.1);
    const Real fine = creepError(checkRun(), 1.0, 20.0, 0.05);
    EXPECT_GT(coarse / fine, 3.5);
    EXPECT_LT(coarse / fine, 4.5);
}

// Creep for t1 = 10 s, then the force removed at once: the elastic part springs back instantly, the Kelvin part
// recovers exponentially, the dashpot's flow F t1 / c_M stays. Within 0.5% of the closed form over 20 s after.
TEST(BurgersSpring, RecoveryMatchesClosedFormAndKeepsTheFlow)
{
    const BurgersParams p = checkRun();
    const Real force = 1.0;
    const Real dt = 0.01;
    const Real t1 = 10.0;
    BurgersState state;
    const BurgersStep jump = burgersStep(p, 0);
    const BurgersStep step = burgersStep(p, dt);
    burgersAdvance(jump, state, force, burgersExtension(jump, state, force));
    for (int i = 1; i <= int(std::llround(t1 / dt)); ++i)
    {
        burgersAdvance(step, state, force, burgersExtension(step, state, force));
    }
    burgersAdvance(jump, state, 0.0, burgersExtension(jump, state, 0.0));
    Real worst = 0;
    for (int i = 1; i <= 2000; ++i)
    {
        burgersAdvance(step, state, 0.0, burgersExtension(step, state, 0.0));
        const Real expected = recoveryExtension(p, force, t1, t1 + i * dt);
        worst = std::max(worst, std::abs(state.extension - expected) / expected);
    }
    EXPECT_LT(worst, 0.005);
    // What is left is the permanent set: the dashpot's flow.
    EXPECT_NEAR(burgersPermanentSet(p, state), force * t1 / p.maxwellDamping, 1e-9);
}

// Relaxation at a held extension: the force starts at k_M eps0 and follows the two-exponential closed form; error
// within 0.5% of the initial force at every step, and within 0.5% of the local value.
TEST(BurgersSpring, RelaxationMatchesClosedForm)
{
    const BurgersParams p = checkRun();
    const Real extension = 0.1;
    const Real dt = 0.01;
    BurgersState state;
    const BurgersStep jump = burgersStep(p, 0);
    burgersAdvance(jump, state, burgersForce(jump, state, extension), extension);
    EXPECT_NEAR(state.force, p.maxwellStiffness * extension, 1e-12);
    const BurgersStep step = burgersStep(p, dt);
    Real worstOfInitial = 0;
    Real worstLocal = 0;
    for (int i = 1; i <= 2000; ++i)
    {
        burgersAdvance(step, state, burgersForce(step, state, extension), extension);
        const Real expected = relaxationForce(p, extension, i * dt);
        worstOfInitial = std::max(worstOfInitial, std::abs(state.force - expected) / (p.maxwellStiffness * extension));
        worstLocal = std::max(worstLocal, std::abs(state.force - expected) / expected);
    }
    EXPECT_LT(worstOfInitial, 0.005);
    EXPECT_LT(worstLocal, 0.005);
}

// With dt > 2 c_K / k_K the trapezoidal Kelvin update would flip sign every step (B < 0); the exponential one is
// used instead, and for a constant force it is exact at any step: creep within 1e-9 at dt = 6 s (2 c_K/k_K = 5 s),
// and the Kelvin extension grows monotonically.
TEST(BurgersSpring, LongStepsUseTheExactExponentialKelvinUpdate)
{
    const BurgersParams p = checkRun();
    const Real dt = 6.0;
    ASSERT_GT(dt, 2 * p.kelvinDamping / p.kelvinStiffness);
    EXPECT_LT(creepError(p, 1.0, 60.0, dt), 1e-9);

    BurgersState state;
    const BurgersStep step = burgersStep(p, dt);
    Real previous = 0;
    for (int i = 0; i < 10; ++i)
    {
        burgersAdvance(step, state, 1.0, burgersExtension(step, state, 1.0));
        EXPECT_GE(state.kelvinExtension, previous);
        EXPECT_LE(state.kelvinExtension, 1.0 / p.kelvinStiffness + 1e-12);
        previous = state.kelvinExtension;
    }
}

// A step much longer than the Maxwell time c_M/k_M (a hot, runny spring at the frame's 0.03 s): the trapezoidal
// factor (1 - x/2)/(1 + x/2) would make the force of a held spring alternate in sign; the exponential Maxwell form
// relaxes it exactly, F = k_M u0 exp(-t k_M / c_M) (1e-12), never changing sign. Creep stays exact too: the dashpot
// flows F dt / c_M per step (1e-12).
TEST(BurgersSpring, LongStepsRelaxAMaxwellSpringExactlyWithoutFlicker)
{
    constexpr Real infinity = std::numeric_limits<Real>::infinity();
    const BurgersParams p{10.0, 1.0, infinity, infinity}; // Maxwell time 0.1 s
    const Real dt = 0.5;
    const Real extension = 0.1;
    BurgersState state;
    const BurgersStep jump = burgersStep(p, 0);
    burgersAdvance(jump, state, burgersForce(jump, state, extension), extension);
    const BurgersStep step = burgersStep(p, dt);
    for (int i = 1; i <= 6; ++i)
    {
        burgersAdvance(step, state, burgersForce(step, state, extension), extension);
        const Real expected =
            p.maxwellStiffness * extension * std::exp(-i * dt * p.maxwellStiffness / p.maxwellDamping);
        EXPECT_GT(state.force, 0.0);
        EXPECT_NEAR(state.force, expected, 1e-12 * p.maxwellStiffness * extension);
    }

    BurgersState creep;
    burgersAdvance(jump, creep, 1.0, burgersExtension(jump, creep, 1.0));
    for (int i = 1; i <= 6; ++i)
    {
        burgersAdvance(step, creep, 1.0, burgersExtension(step, creep, 1.0));
        EXPECT_NEAR(creep.extension, 1.0 / p.maxwellStiffness + i * dt / p.maxwellDamping, 1e-12);
    }
}

// The same creep through the engine: a mass on a spring pulled by a constant force, the spring driven by the
// ViscoelasticSprings hook (its k_eff and effective rest length) and the implicit integrator. The mass is light
// (1 g against k_M = 10 N/m: a 0.06 s period, damped by backward Euler within 0.1 s), so after 1 s the extension is
// the quasi-static creep of the closed form, within 0.5%. The engine feels the load from the end of its first step,
// so the flow starts about dt/2 late: an error of F dt/2 (1/c_M + 1/c_K) = 0.05% of the 1 s creep at dt = 2 ms (and
// 0.27% at 10 ms). Coefficients come from the material at the spring's temperature with k/E = 1 m, so
// k_M = E(T), c_M = 3 eta(T) (Trouton).
TEST(BurgersSpring, CreepThroughSimulatorAndHookMatchesClosedForm)
{
    Material material;
    material.glassTransition = 300;
    material.transitionTemperature = 300;
    material.upperTemperature = 400;
    auto law = std::make_shared<WlfLaw>();
    law->rubberyModulus = 10;
    law->glassyModulus = 1e4;
    law->viscosityAtTransition = 40.0 / 3.0 * std::pow(10.0, 17.44 * 100 / 151.6); // c_M about 40 N s/m at 400 K
    material.law = law;
    material.kelvinModulusRatio = 0.2;
    material.kelvinViscosityRatio = 0.125;
    material.forming = FormingWindow{350, 380, 390, 290};
    const Real temperature = 400;

    MassSpringSystem system = makeChain(2, 1e-3, 0.0, 1.0);
    system.particles.setPinned(0, true);
    const Real force = 1.0;
    system.particles.externalForce[1] = Vec3(force, 0, 0);
    SpringModelSettings settings;
    settings.model = SpringModel::Burgers;
    settings.dampingRatio = 0;
    settings.initialTemperature = temperature;
    ViscoelasticSprings springs(system, {1.0}, material, settings);

    BurgersParams p;
    p.maxwellStiffness = modulusAt(material, temperature);
    p.maxwellDamping = 3 * viscosityAt(material, temperature);
    p.kelvinStiffness = material.kelvinModulusRatio * p.maxwellStiffness;
    p.kelvinDamping = material.kelvinViscosityRatio * p.maxwellDamping;
    ASSERT_NEAR(p.maxwellDamping, 40.0, 1.0);

    Simulator simulator(std::move(system), SimulatorSettings{});
    simulator.addHook(&springs);
    Real worst = 0;
    simulate(simulator, 20.0, 0.002,
             [&](const Simulator& s)
             {
                 if (s.time() < 1.0)
                 {
                     return;
                 }
                 const Real extension = s.system().particles.position[1].x() - 1.0;
                 const Real expected = creepExtension(p, force, s.time());
                 worst = std::max(worst, std::abs(extension - expected) / expected);
             });
    EXPECT_LT(worst, 0.005);
    RecordProperty("hook_creep_relative_error", std::to_string(worst));
    // The hook's own state agrees with the mass's position.
    EXPECT_NEAR(springs.states()[0].force, force, 1e-3 * force);
}
