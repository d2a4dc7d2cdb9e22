#include "core/DivergenceGuard.h"

#include "core/Format.h"
#include "core/NumericalError.h"
#include "core/forces/Energy.h"
#include "core/forces/SimdPath.h"
#include "core/forces/SpringEnergyKernels.h"
#include "core/parallel/ChunkedSum.h"

#include <algorithm>
#include <cmath>
#include <cstring>

namespace masse
{
namespace
{
/// Springs per chunk of the energy sum: a fixed constant, so the sum's bits do not depend on the thread count.
constexpr std::size_t springEnergyChunkSize = 8192;

/// Potential of a grab spring whose pull is capped at F: 1/2 k d^2 up to d_c = F/k, then F d - F^2/(2k).
Real cappedSpringPotential(const UserSpring& spring, Real distance)
{
    const Real cap = spring.stiffness > 0 ? spring.maxForce / spring.stiffness : std::numeric_limits<Real>::infinity();
    if (distance <= cap)
    {
        return Real(0.5) * spring.stiffness * distance * distance;
    }
    return spring.maxForce * distance - Real(0.5) * spring.maxForce * cap;
}

/// The grabs' stored energy (their springs capped as above).
Real grabEnergy(const MassSpringSystem& system)
{
    Real energy = 0;
    for (const UserSpring& spring : system.userSprings.all())
    {
        energy += cappedSpringPotential(spring, (system.particles.position[spring.mass] - spring.target).norm());
    }
    return energy;
}

/// The sheet's weight times its size: the energy a fall of its own size gives it, the guard's unit of energy.
Real energyScale(const MassSpringSystem& system)
{
    const Particles& p = system.particles;
    if (p.size() == 0)
    {
        return 0;
    }
    Real mass = 0;
    Vec3 lo = p.position[0];
    Vec3 hi = lo;
    for (std::size_t i = 0; i < p.size(); ++i)
    {
        mass += p.mass[i];
        lo = lo.cwiseMin(p.position[i]);
        hi = hi.cwiseMax(p.position[i]);
    }
    const Real size = std::max((hi - lo).norm(), Real(0.01));
    const Real acceleration = std::max(system.forces.gravity.norm(), Real(1));
    return mass * acceleration * size;
}

/// Gravity's part of the mechanical energy (J): what is left is kinetic and elastic, never negative.
Real gravityEnergy(const MassSpringSystem& system)
{
    const Particles& p = system.particles;
    Real energy = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
    {
        if (!p.pinned[i])
        {
            energy -= p.mass[i] * system.forces.gravity.dot(p.position[i]);
        }
    }
    return energy;
}

/// Kinetic and gravity energy of the free masses (J), summed in fixed chunks over ranges on all threads.
Real massEnergy(const MassSpringSystem& system)
{
    const Particles& p = system.particles;
    const Vec3 gravity = system.forces.gravity;
    return chunkedSum(p.size(), massChunkSize,
                      [&](std::size_t begin, std::size_t end)
                      {
                          Real energy = 0;
                          for (std::size_t i = begin; i < end; ++i)
                          {
                              if (!p.pinned[i])
                              {
                                  energy += p.mass[i] *
                                            (Real(0.5) * p.velocity[i].squaredNorm() - gravity.dot(p.position[i]));
                              }
                          }
                          return energy;
                      });
}
} // namespace

namespace
{
/// Kinetic energy of the free masses (J), in fixed chunks.
Real kineticEnergy(const MassSpringSystem& system)
{
    const Particles& p = system.particles;
    return chunkedSum(p.size(), massChunkSize,
                      [&](std::size_t begin, std::size_t end)
                      {
                          Real energy = 0;
                          for (std::size_t i = begin; i < end; ++i)
                          {
                              if (!p.pinned[i])
                              {
                                  energy += Real(0.5) * p.mass[i] * p.velocity[i].squaredNorm();
                              }
                          }
                          return energy;
                      });
}

/// The springs' energy (J): a spring pass over ranges on all threads, summed in fixed chunks (the guard's figure is the
/// same at any thread count).
Real springsEnergy(const MassSpringSystem& system)
{
    const SimdPath path = activeSimdPath();
    return chunkedSum(system.springs.size(), springEnergyChunkSize,
                      [&](std::size_t begin, std::size_t end)
                      { return springEnergyOfRange(path, system, begin, end); });
}
} // namespace

Real motionEnergy(const MassSpringSystem& system)
{
    return massEnergy(system) + grabEnergy(system);
}

Real mechanicalEnergy(const MassSpringSystem& system)
{
    // Each sum in its own order, so the guard's memo (DivergenceGuard::mechanical) has the same bits.
    const Real masses = massEnergy(system);
    const Real springs = springsEnergy(system);
    return masses + springs + grabEnergy(system);
}

bool DivergenceGuard::SpringEnergyMemo::holds(const MassSpringSystem& system) const
{
    const std::vector<Vec3>& x = system.particles.position;
    return valid && revision == system.revision && springs == system.springs.size() && positions.size() == x.size() &&
           std::memcmp(positions.data(), x.data(), x.size() * sizeof(Vec3)) == 0;
}

void DivergenceGuard::SpringEnergyMemo::keep(const MassSpringSystem& system, Real springEnergy)
{
    valid = true;
    revision = system.revision;
    springs = system.springs.size();
    positions = system.particles.position; // capacity kept: no allocation after the first
    energy = springEnergy;
}

Real DivergenceGuard::mechanical(const MassSpringSystem& system) const
{
    const Real masses = massEnergy(system);
    if (!m_springMemo.holds(system))
    {
        m_springMemo.keep(system, springsEnergy(system));
    }
    return masses + m_springMemo.energy + grabEnergy(system);
}

Real DivergenceGuard::hooksEnergy(const MassSpringSystem& system) const
{
    const Real kinetic = kineticEnergy(system);
    return m_settings.account == EnergyAccount::Mechanical ? mechanical(system) - kinetic
                                                           : motionEnergy(system) - kinetic;
}

void DivergenceGuard::beforeHooks(const MassSpringSystem& system)
{
    if (!m_settings.enabled || !m_settings.checkEnergy)
    {
        return;
    }
    if (!m_inStep)
    {
        // The first pass of a step.
        m_inStep = true;
        if (!m_started)
        {
            // The reference holds the springs' energy in either account: what they hold at the start may turn into
            // motion.
            const Real energy = mechanical(system);
            m_started = true;
            m_reference = energy;
            m_scale = energyScale(system) + std::max(Real(0), energy - gravityEnergy(system));
        }
        else
        {
            // What changed since the last step's check was done from outside (a viewer's pick moving its target, a
            // pin, a teleported mass): put in.
            m_putIn += std::max(Real(0), energyBetweenSteps(system) - m_lastEnergy);
        }
        m_stepStart = system.particles.position;
    }
    m_hooksRevision = system.revision;
    m_hooksGrabEnergy = grabEnergy(system);
    m_hooksMeasured = m_measureEveryPass;
    if (m_hooksMeasured)
    {
        m_hooksEnergy = hooksEnergy(system);
    }
}

void DivergenceGuard::afterHooks(const MassSpringSystem& system)
{
    if (!m_settings.enabled || !m_settings.checkEnergy)
    {
        return;
    }
    if (system.revision != m_hooksRevision)
    {
        m_changedInFirstStep = true;
    }
    if (m_hooksMeasured)
    {
        m_putIn += std::max(Real(0), hooksEnergy(system) - m_hooksEnergy);
        return;
    }
    if (system.revision != m_hooksRevision)
    {
        // A hook changed gravity, pins or springs, unmeasured: start the accounting again after this step, and
        // measure every pass from now on, as it may keep doing so (a material model does it every substep).
        m_rebase = true;
        m_measureEveryPass = true;
        return;
    }
    m_putIn += std::max(Real(0), grabEnergy(system) - m_hooksGrabEnergy); // grab targets moved
}

namespace
{
/// The most energy one contact pass may add and have it counted as put in, in units of the sheet's energy scale.
constexpr Real contactCreditLimit = 5;

/// Two figures from one spring pass after an implicit substep, each summed in the chunks and order it would have
/// alone (the gap's chunk sums kept in `gapPartial`, whose capacity is kept).
struct SpringPass
{
    Real energy = 0; ///< J, the springs' energy: mechanicalEnergy's spring part
    /// J, the linearisation gap: how much the springs' energy at the end of the substep exceeds the quadratic model the
    /// linearised solve minimised (the springs' energy at the substep's start, its force and its stiffness there, with
    /// the compressed springs' negative transverse stiffness left out as the solver leaves it out). The linearised
    /// step dissipates the model's energy; what the true springs hold beyond it is the integrator's known error: a
    /// straight, compressed chain buckling, or a glassy sheet's springs of meganewtons per metre turning.
    Real gap = 0;
};
SpringPass springEnergyAndGap(const MassSpringSystem& system, const std::vector<Vec3>& start,
                              std::vector<Real>& gapPartial)
{
    const SimdPath path = activeSimdPath();
    gapPartial.resize(chunkCount(system.springs.size(), springEnergyChunkSize));
    SpringPass pass;
    pass.energy = chunkedSum(system.springs.size(), springEnergyChunkSize,
                             [&](std::size_t begin, std::size_t end)
                             {
                                 const SpringEnergyAndGap range =
                                     springEnergyAndGapOfRange(path, system, start, begin, end);
                                 gapPartial[begin / springEnergyChunkSize] = range.gap;
                                 return range.energy;
                             });
    for (const Real partial : gapPartial) // in chunk order
    {
        pass.gap += partial;
    }
    return pass;
}
} // namespace

void DivergenceGuard::beforeSubstep(const MassSpringSystem& system, IntegratorKind integrator)
{
    if (m_settings.enabled && m_settings.checkEnergy && !isExplicit(integrator))
    {
        m_substepStart = system.particles.position;
    }
}

void DivergenceGuard::afterIntegrator(const MassSpringSystem& system, IntegratorKind integrator)
{
    if (m_settings.enabled && m_settings.checkEnergy && !isExplicit(integrator) &&
        m_substepStart.size() == system.particles.size())
    {
        if (m_settings.account == EnergyAccount::Mechanical)
        {
            // mechanicalEnergy's sum, its spring pass shared with the gap's.
            const Real masses = massEnergy(system);
            const SpringPass pass = springEnergyAndGap(system, m_substepStart, m_gapPartial);
            m_linearisationError = Real(0.5) * m_linearisationError + pass.gap;
            m_contactEnergy = masses + pass.energy + grabEnergy(system);
            m_springMemo.keep(system, pass.energy);
        }
        else
        {
            m_contactEnergy = accountedEnergy(system);
        }
        m_contactStart = system.particles.position;
    }
}

void DivergenceGuard::afterContact(const MassSpringSystem& system, IntegratorKind integrator)
{
    if (!m_settings.enabled || !m_settings.checkEnergy || isExplicit(integrator) ||
        m_contactStart.size() != system.particles.size() || m_substepStart.size() != system.particles.size())
    {
        return;
    }
    const Real added = accountedEnergy(system) - m_contactEnergy;
    if (!(added > 0))
    {
        return;
    }
    constexpr Real tolerance = 1e-3; // m
    const std::vector<Vec3>& x = system.particles.position;
    for (std::size_t i = 0; i < x.size(); ++i)
    {
        const Real moved = (x[i] - m_contactStart[i]).norm();
        if (moved > (m_contactStart[i] - m_substepStart[i]).norm() + tolerance)
        {
            return; // thrown farther than it came: not an undone move
        }
    }
    // Even an undone move stores no more than a few times the sheet's energy scale (the flattened landing above: 3.6
    // times); a pass that adds more is not credited.
    if (added <= contactCreditLimit * m_scale)
    {
        m_putIn += added;
    }
}

void DivergenceGuard::checkSpeedBeforeContact(const MassSpringSystem& system, const GuardStep& step)
{
    if (!m_settings.enabled || std::isinf(m_settings.speedLimit))
    {
        return;
    }
    const Particles& p = system.particles;
    // Velocities in units of the bound: their squares stay finite for bounds and speeds near double's range.
    const Real inverse = 1 / m_settings.speedLimit;
    for (std::size_t i = 0; i < p.size(); ++i)
    {
        // Written so that a NaN speed fails too (the finite check at the step's end would name it later).
        if (!p.pinned[i] && !((p.velocity[i] * inverse).squaredNorm() <= 1))
        {
            fail(step,
                 "mass " + std::to_string(i) + " moves at " + formatNumber("%.3g", p.velocity[i].stableNorm()) +
                     " m/s before the contact pass, above this "
                     "scene's bound of " +
                     formatNumber("%.3g", m_settings.speedLimit) +
                     " m/s (100 times the fastest that gravity, the scripted motions and a forming pressure can give)");
        }
    }
}

void DivergenceGuard::check(const MassSpringSystem& system, const GuardStep& step)
{
    if (!m_settings.enabled)
    {
        return;
    }
    const Real dt = step.dt;
    const Particles& p = system.particles;
    // Finite state (the sum vectorises; the search runs only on failure) and the speed bound.
    Real sum = 0;
    Real fastest = 0;
    std::size_t fastestMass = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
    {
        sum += p.position[i].sum() + p.velocity[i].sum();
        const Real speed = p.pinned[i] ? Real(0) : p.velocity[i].squaredNorm();
        if (speed > fastest)
        {
            fastest = speed;
            fastestMass = i;
        }
    }
    if (!std::isfinite(sum))
    {
        for (std::size_t i = 0; i < p.size(); ++i)
        {
            if (!p.position[i].allFinite() || !p.velocity[i].allFinite())
            {
                fail(step, "mass " + std::to_string(i) + " has a non-finite position or velocity");
            }
        }
        fail(step, "positions or velocities grew beyond the range of double precision");
    }
    fastest = std::sqrt(fastest);
    if (fastest > m_settings.speedLimit)
    {
        // stableNorm: the squared speed may have overflowed where the speed has not.
        fail(step,
             "mass " + std::to_string(fastestMass) + " moves at " +
                 formatNumber("%.3g", p.velocity[fastestMass].stableNorm()) + " m/s, above this scene's bound of " +
                 formatNumber("%.3g", m_settings.speedLimit) +
                 " m/s (100 times the fastest that gravity, the scripted motions and a forming pressure can give)");
    }
    m_inStep = false;
    if (!m_settings.checkEnergy)
    {
        return;
    }

    // Energy: what the sheet has against what it started with plus what was put in.
    const Real energy = accountedEnergy(system);
    if (m_rebase)
    {
        // A change within the hooks that was not measured (before the guard knew to measure them): the accounting
        // starts again from here.
        const Real mechanicalNow = m_settings.account == EnergyAccount::Mechanical ? energy : mechanical(system);
        m_rebase = false;
        m_reference = mechanicalNow;
        m_putIn = 0;
        m_integratorError = 0;
        m_linearisationError = 0;
        m_scale = energyScale(system) + std::max(Real(0), mechanicalNow - gravityEnergy(system));
    }
    else
    {
        if (step.contactForce && m_settings.obstacleSpeed > 0)
        {
            // A moving obstacle works on what touches it at most with its contact force times its speed. A mass stuck
            // to it is held in place, not pushed, so its contact force is what the rest of the sheet and gravity pull
            // it with, its net force without contact: take the larger of the two for every mass.
            Real push = 0;
            for (std::size_t i = 0; i < step.contactForce->size() && i < p.size(); ++i)
            {
                push += std::max((*step.contactForce)[i].norm(), p.force[i].norm());
            }
            m_putIn += push * m_settings.obstacleSpeed * dt;
        }
        // A grab whose target moves at u works on the sheet within the step (the integrator moves the target with u
        // as it solves): at most |F| |u| per grab, F its pull (spring and damper).
        std::vector<Vec3> grabPull;
        for (const UserSpring& spring : system.userSprings.all())
        {
            const UserSpringForce pull = evaluateUserSpring(spring, p.position[spring.mass], p.velocity[spring.mass]);
            m_putIn += pull.force.norm() * spring.targetVelocity.norm() * dt;
            grabPull.push_back(pull.force);
        }
        // Applied forces (pressure, scripted forces) work at most their size times how far their masses moved.
        const bool explicitEuler = step.integrator == IntegratorKind::ExplicitEuler;
        Real steadyForceSquared = 0; // sum over free masses of |f|^2 / m for the steady forces f on them
        for (std::size_t i = 0; i < p.size(); ++i)
        {
            if (p.pinned[i])
            {
                continue;
            }
            const Vec3& applied = p.externalForce[i];
            if (i < m_stepStart.size())
            {
                m_putIn += applied.norm() * (p.position[i] - m_stepStart[i]).norm();
            }
            if (explicitEuler)
            {
                steadyForceSquared += (p.mass[i] * system.forces.gravity + applied).squaredNorm() * p.inverseMass[i];
            }
        }
        if (explicitEuler)
        {
            for (std::size_t g = 0; g < grabPull.size(); ++g)
            {
                steadyForceSquared += grabPull[g].squaredNorm() * p.inverseMass[system.userSprings.all()[g].mass];
            }
            // Explicit Euler's own gain: h^2 |f|^2 / (2 m) per substep, dt / h substeps; twice that, for the forces
            // that vary over the step (a swinging chain's tension).
            m_integratorError += steadyForceSquared * step.substep * dt;
        }
        const Real slack = m_settings.energySlack * (m_scale + m_putIn);
        const Real allowed = m_reference + m_putIn + integratorAllowance() + slack;
        if (energy > allowed)
        {
            fail(step, "the sheet's energy grew to " + formatNumber("%.4g", energy - m_reference) +
                           " J above its start, more than the " + formatNumber("%.4g", m_putIn) +
                           " J that grabs, applied forces, moving obstacles and heat put in (plus " +
                           formatNumber("%.3g", integratorAllowance()) + " J of the " +
                           std::string(integratorName(step.integrator)) + " integrator's known error and a slack of " +
                           formatNumber("%.3g", slack) + " J); the fastest mass is " + std::to_string(fastestMass) +
                           " at " + formatNumber("%.3g", fastest) + " m/s");
        }
    }
    m_lastEnergy = energy;
    m_lastGrabEnergy = grabEnergy(system);
    m_lastRevision = system.revision;
    if (!m_measureDecided)
    {
        // After the first step: if no hook changed the springs or pins in it, measure only the grab targets.
        m_measureDecided = true;
        m_measureEveryPass = m_changedInFirstStep;
    }
}

Real DivergenceGuard::energyBetweenSteps(const MassSpringSystem& system) const
{
    if (system.revision != m_lastRevision)
    {
        return accountedEnergy(system);
    }
    // Unmarked, only grab targets may have moved (a viewer's pick drags its target without marking a change): the
    // state is the one the last check measured, which saves a spring pass a step (3-5% of an explicit step at 128).
    return m_lastEnergy - m_lastGrabEnergy + grabEnergy(system);
}

Real DivergenceGuard::accountedEnergy(const MassSpringSystem& system) const
{
    return m_settings.account == EnergyAccount::Mechanical ? mechanical(system) : motionEnergy(system);
}

void DivergenceGuard::fail(const GuardStep& step, const std::string& what) const
{
    // The remedy fits the integrator: an implicit run is not sent to the implicit integrator. The scene layer names the
    // keys; the engine speaks of its own quantities.
    const std::string remedy = isExplicit(step.integrator)
                                   ? "Try a smaller step dt, the implicit integrator, or softer springs"
                                   : "Try a smaller step dt or softer springs (the implicit integrator too can diverge "
                                     "where contact or a grab changes the forces faster than a step resolves)";
    throw NumericalError("the simulation diverged at t = " + formatNumber("%.4g", step.time) + " s: " + what + ". " +
                         remedy + "; no frame of this state was written");
}
} // namespace masse
