#include "Simulator.h"

#include "InputError.h"

#include <cmath>
#include <string>

namespace masse
{
Simulator::Simulator(MassSpringSystem system, const SimulatorSettings& settings)
    : m_system(std::move(system)), m_settings(settings),
      m_integrator(makeIntegrator(settings.integrator, settings.implicit))
{
}

void Simulator::setIntegrator(IntegratorKind kind)
{
    m_settings.integrator = kind;
    m_integrator = makeIntegrator(kind, m_settings.implicit);
    m_system.markChanged();
}

const StabilityEstimate& Simulator::stability() const
{
    if (m_stabilityRevision != m_system.revision || m_system.forces.repulsion > 0)
    {
        m_stability = estimateStability(m_system, m_settings.integrator, m_settings.stabilitySafety);
        m_stabilityRevision = m_system.revision;
    }
    return m_stability;
}

int Simulator::substepsFor(Real dt) const
{
    if (!(dt > 0) || !std::isfinite(dt))
    {
        throw InputError("dt: must be a positive number of seconds (got " + std::to_string(dt) + ")");
    }
    const StabilityEstimate& estimate = stability();
    if (!std::isfinite(estimate.stableStep))
    {
        return 1;
    }
    const Real needed = std::ceil(dt / estimate.stableStep);
    if (needed > Real(m_settings.maxSubsteps))
    {
        throw InputError("dt: the " + std::string(integratorName(m_settings.integrator)) + " integrator needs " +
                         std::to_string(std::llround(needed)) + " substeps of at most " +
                         std::to_string(estimate.stableStep) + " s for dt = " + std::to_string(dt) +
                         " s, over the limit of " + std::to_string(m_settings.maxSubsteps) +
                         "; use the implicit integrator or softer springs");
    }
    return std::max(1, int(needed));
}

StepReport Simulator::step(Real dt)
{
    StepReport report;
    report.substeps = substepsFor(dt);
    report.substep = dt / Real(report.substeps);
    if (m_contact)
    {
        m_contact->beginFrame(m_system, m_time, dt, m_integrator->honoursConstraints());
    }
    m_guard.beforeHooks(m_system);
    for (StepHook* hook : m_hooks)
    {
        hook->beginFrame(m_system, m_time, dt);
    }
    m_guard.afterHooks(m_system);
    for (int i = 0; i < report.substeps; ++i)
    {
        const IntegratorStats stats = m_integrator->step(m_system, report.substep);
        report.solverIterations += stats.solverIterations;
        report.solverResidual = std::max(report.solverResidual, stats.solverResidual);
        if (m_contact)
        {
            m_contact->afterSubstep(m_system, report.substep);
        }
        const Real substepEnd = m_time + Real(i + 1) * report.substep;
        m_guard.beforeHooks(m_system);
        for (StepHook* hook : m_hooks)
        {
            hook->afterSubstep(m_system, report.substep, substepEnd);
        }
        m_guard.afterHooks(m_system);
    }
    m_substepCount += std::uint64_t(report.substeps);
    m_time += dt;
    if (m_contact)
    {
        m_contact->endFrame(m_system, m_time);
    }
    m_guard.beforeHooks(m_system);
    for (StepHook* hook : m_hooks)
    {
        hook->endFrame(m_system, m_time);
    }
    m_guard.afterHooks(m_system);
    m_guard.check(m_system, m_time, dt, m_contact ? &m_contact->contactForce() : nullptr);
    return report;
}

} // namespace masse
