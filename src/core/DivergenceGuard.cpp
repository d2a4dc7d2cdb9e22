#include "DivergenceGuard.h"

#include "Energy.h"
#include "Format.h"
#include "SpringForce.h"

#include <algorithm>
#include <cmath>

namespace masse
{
namespace
{
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
} // namespace

Real mechanicalEnergy(const MassSpringSystem& system)
{
    const Particles& p = system.particles;
    Real energy = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
    {
        if (!p.pinned[i])
        {
            energy += p.mass[i] * (Real(0.5) * p.velocity[i].squaredNorm() - system.forces.gravity.dot(p.position[i]));
        }
    }
    const SpringSet& s = system.springs;
    for (std::size_t k = 0; k < s.size(); ++k)
    {
        const Real length = (p.position[s.ends[k].a] - p.position[s.ends[k].b]).norm();
        energy += springPotential(length, s.stiffness[k], s.restLength[k], system.forces.repulsion);
    }
    return energy + [&]
    {
        Real grabs = 0;
        for (const UserSpring& spring : system.userSprings.all())
        {
            grabs += cappedSpringPotential(spring, (p.position[spring.mass] - spring.target).norm());
        }
        return grabs;
    }();
}

Real DivergenceGuard::grabEnergy(const MassSpringSystem& system)
{
    Real energy = 0;
    for (const UserSpring& spring : system.userSprings.all())
    {
        energy += cappedSpringPotential(spring, (system.particles.position[spring.mass] - spring.target).norm());
    }
    return energy;
}

void DivergenceGuard::beforeHooks(const MassSpringSystem& system)
{
    if (!m_settings.enabled)
    {
        return;
    }
    if (!m_inStep)
    {
        // The first pass of a step: what changed since the last step's check was done from outside (a viewer's
        // pick moving its target, a pin): grab targets moved are put in, anything else restarts the accounting.
        m_inStep = true;
        if (m_started && system.revision != m_lastRevision)
        {
            m_rebase = true;
        }
        m_putIn += std::max(Real(0), grabEnergy(system) - m_lastGrabEnergy);
    }
    m_hooksRevision = system.revision;
    m_hooksGrabEnergy = grabEnergy(system);
    m_hooksMeasured = m_measureEveryPass;
    if (m_hooksMeasured)
    {
        m_hooksEnergy = mechanicalEnergy(system);
    }
}

void DivergenceGuard::afterHooks(const MassSpringSystem& system)
{
    if (!m_settings.enabled)
    {
        return;
    }
    if (m_hooksMeasured)
    {
        m_putIn += std::max(Real(0), mechanicalEnergy(system) - m_hooksEnergy);
        return;
    }
    if (system.revision != m_hooksRevision)
    {
        // A hook changed gravity, pins or springs, unmeasured: start the accounting again after this step, and
        // measure every pass from now on if it keeps doing so (a material model does it every substep).
        m_rebase = true;
        m_measureEveryPass = true;
        return;
    }
    m_putIn += std::max(Real(0), grabEnergy(system) - m_hooksGrabEnergy); // grab targets moved
}

void DivergenceGuard::check(const MassSpringSystem& system, Real time, Real dt, const std::vector<Vec3>* contactForce)
{
    if (!m_settings.enabled)
    {
        return;
    }
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
                fail(time, "mass " + std::to_string(i) + " has a non-finite position or velocity");
            }
        }
        fail(time, "positions or velocities grew beyond the range of double precision");
    }
    fastest = std::sqrt(fastest);
    if (fastest > m_settings.speedLimit)
    {
        fail(time, "mass " + std::to_string(fastestMass) + " moves at " + formatNumber("%.3g", fastest) +
                       " m/s, above this scene's bound of " + formatNumber("%.3g", m_settings.speedLimit) +
                       " m/s (100 times the fastest that gravity and the scripted motions can give)");
    }

    if (m_measureEveryPass || !m_settings.checkEnergy)
    {
        // A hook rewrites the springs every substep (a material's Burgers springs): their stiffness and rest length
        // are then a per-step linearisation of a dissipative element, and 1/2 k (l - L)^2 is not a stored energy (a
        // cold glassy sheet falling at 0.8 m/s read as tens of joules). The finite and speed checks still hold.
        m_inStep = false;
        m_lastGrabEnergy = grabEnergy(system);
        m_lastRevision = system.revision;
        return;
    }
    // Energy: what the sheet has against what it started with plus what was put in.
    const Real energy = mechanicalEnergy(system);
    m_inStep = false;
    if (!m_started || m_rebase)
    {
        // The first step, or a change between steps or within the hooks that was not measured (a pin, a new grab):
        // the accounting starts again from here.
        m_started = true;
        m_rebase = false;
        m_reference = energy;
        m_putIn = 0;
        m_scale = energyScale(system);
    }
    else
    {
        if (contactForce && m_settings.obstacleSpeed > 0)
        {
            // A moving obstacle works on what touches it at most with its contact force times its speed. A mass stuck
            // to it is held in place, not pushed, so its contact force is what the rest of the sheet and gravity pull
            // it with, its net force without contact: take the larger of the two for every mass.
            Real push = 0;
            for (std::size_t i = 0; i < contactForce->size() && i < p.size(); ++i)
            {
                push += std::max((*contactForce)[i].norm(), p.force[i].norm());
            }
            m_putIn += push * m_settings.obstacleSpeed * dt;
        }
        // A grab whose target moves at u works on the sheet within the step (the integrator moves the target with u
        // as it solves): at most |F| |u| per grab, F its pull (spring and damper).
        for (const UserSpring& spring : system.userSprings.all())
        {
            const UserSpringForce pull = evaluateUserSpring(spring, p.position[spring.mass], p.velocity[spring.mass]);
            m_putIn += pull.force.norm() * spring.targetVelocity.norm() * dt;
        }
        const Real allowed = m_reference + m_putIn + m_settings.energySlack * (m_scale + m_putIn);
        if (energy > allowed)
        {
            fail(time, "the sheet's energy grew to " + formatNumber("%.4g", energy - m_reference) +
                           " J above its start, more than the " + formatNumber("%.4g", m_putIn) +
                           " J that grabs, moving obstacles and heat put in (plus a slack of " +
                           formatNumber("%.3g", m_settings.energySlack * (m_scale + m_putIn)) +
                           " J); the fastest mass is " + std::to_string(fastestMass) + " at " +
                           formatNumber("%.3g", fastest) + " m/s");
        }
    }
    m_lastGrabEnergy = grabEnergy(system);
    m_lastRevision = system.revision;
}

void DivergenceGuard::fail(Real time, const std::string& what) const
{
    throw NumericalError("the simulation diverged at t = " + formatNumber("%.4g", time) + " s: " + what +
                         ". Try a smaller step (integrator.dt), the implicit integrator (\"integrator\": {\"type\": "
                         "\"implicit\"}), or softer springs; no frame of this state was written");
}
} // namespace masse
