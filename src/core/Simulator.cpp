#include "core/Simulator.h"

#include "core/Format.h"
#include "core/InputError.h"
#include "core/NumericalError.h"
#include "core/forces/Forces.h"
#include "core/parallel/TaskPool.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace masse
{
Simulator::Simulator(MassSpringSystem system, const SimulatorSettings& settings)
    : Simulator(std::move(system), settings, std::make_shared<TaskPool>(settings.threads))
{
}

Simulator::Simulator(MassSpringSystem system, const SimulatorSettings& settings, std::shared_ptr<TaskPool> pool)
    : m_system(std::move(system)), m_settings(settings), m_pool(std::move(pool)),
      m_integrator(makeIntegrator(settings.integrator, settings.implicit))
{
    if (!m_pool)
    {
        throw std::invalid_argument("Simulator: no task pool");
    }
    m_settings.threads = m_pool->threadCount();
}

void Simulator::setThreadCount(int threads)
{
    if (threads != m_pool->threadCount() || m_pool.use_count() > 1)
    {
        m_pool = std::make_shared<TaskPool>(threads);
    }
    m_settings.threads = threads;
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
        m_stability =
            estimateStability(m_system, m_settings.integrator, m_settings.stabilitySafety, m_settings.stabilityMethod);
        m_stabilityRevision = m_system.revision;
    }
    return m_stability;
}

namespace
{
void requirePositiveStep(Real dt)
{
    if (!(dt > 0) || !std::isfinite(dt))
    {
        throw InputError("dt", "must be a positive number of seconds (got " + formatNumber(dt) + ")");
    }
}
} // namespace

int Simulator::substepsFor(Real dt) const
{
    requirePositiveStep(dt);
    const PoolScope threads(*m_pool);
    const StabilityEstimate& estimate = stability();
    if (!std::isfinite(estimate.stableStep))
    {
        return 1;
    }
    const Real needed = std::ceil(dt / estimate.stableStep);
    if (needed > Real(m_settings.maxSubsteps))
    {
        // formatNumber, not llround or std::to_string: a count past 2^63 or a step below 1e-6 s stays readable.
        throw InputError("dt", "the " + std::string(integratorName(m_settings.integrator)) + " integrator needs " +
                                   formatNumber(needed) + " substeps of at most " + formatNumber(estimate.stableStep) +
                                   " s for dt = " + formatNumber(dt) + " s, over the limit of " +
                                   std::to_string(m_settings.maxSubsteps) +
                                   "; use the implicit integrator or softer springs");
    }
    return std::max(1, int(needed));
}

StepReport Simulator::step(Real dt)
{
    const PoolScope threads(*m_pool);
    if (isExplicit(m_settings.integrator))
    {
        return stepFrame(dt);
    }
    requirePositiveStep(dt); // a bad dt is refused before a hook is asked about it
    int solves = 1;
    for (StepHook* hook : m_hooks)
    {
        solves = std::max(solves, hook->solvesFor(m_system, dt));
    }
    if (solves == 1)
    {
        return stepFrame(dt);
    }
    StepReport report;
    for (int k = 0; k < solves; ++k)
    {
        const StepReport part = stepFrame(dt / Real(solves));
        report.substeps += part.substeps;
        report.substep = part.substep;
        report.solverIterations += part.solverIterations;
        report.solverResidual = std::max(report.solverResidual, part.solverResidual);
        report.solverCapHits += part.solverCapHits;
    }
    return report;
}

StepReport Simulator::stepFrame(Real dt)
{
    // Every stage of the hooks, in the order added; the guard accounts for the energy they put in or take out.
    const auto runHooks = [this](const auto& stage)
    {
        m_guard.beforeHooks(m_system);
        for (StepHook* hook : m_hooks)
        {
            stage(*hook);
        }
        m_guard.afterHooks(m_system);
    };
    StepReport report;
    runHooks([&](StepHook& hook) { hook.beforeFrame(m_system, m_context, m_time); });
    report.substeps = substepsFor(dt);
    report.substep = dt / Real(report.substeps);
    m_context.oneSolveAFrame = !isExplicit(m_settings.integrator);
    m_context.constraints.clear(); // the contact solver clears them too; without one, the self-contact's are here
    if (m_contact)
    {
        m_contact->beginFrame(m_system, m_context, m_time, dt, m_integrator->honoursConstraints());
        publishContact();
    }
    runHooks([&](StepHook& hook) { hook.beginFrame(m_system, m_context, m_time, dt); });
    // Only the symplectic pass skips zero external forces; the hooks may write them (a pressure load does).
    const bool watchExternalForces = m_settings.integrator == IntegratorKind::SymplecticEuler;
    const auto lookForExternalForces = [&]
    { m_context.externalForces = !watchExternalForces || !noExternalForces(m_system.particles); };
    lookForExternalForces();
    const bool hooksWriteExternalForces =
        watchExternalForces && std::any_of(m_hooks.begin(), m_hooks.end(),
                                           [](const StepHook* hook) { return hook->writesExternalForcesMidFrame(); });
    const bool hooksReadForces =
        std::any_of(m_hooks.begin(), m_hooks.end(), [](const StepHook* hook) { return hook->readsForcesMidFrame(); });
    for (int i = 0; i < report.substeps; ++i)
    {
        m_context.forcesRead = i + 1 == report.substeps || hooksReadForces || (m_contact && m_contact->readsForces());
        m_guard.beforeSubstep(m_system, m_settings.integrator);
        m_context.moveStep = report.substep;
        const IntegratorStats stats = m_integrator->step(m_system, m_context, report.substep);
        report.solverIterations += stats.solverIterations;
        report.solverResidual = std::max(report.solverResidual, stats.solverResidual);
        report.solverCapHits += stats.hitIterationCap ? 1 : 0;
        if (!isExplicit(m_settings.integrator))
        {
            m_solverTally.add(stats);
        }
        m_guard.afterIntegrator(m_system, m_settings.integrator);
        const Real substepEnd = m_time + Real(i + 1) * report.substep;
        if (m_context.oneSolveAFrame)
        {
            runHooks([&](StepHook& hook) { hook.afterImplicitSolve(m_system, m_context, report.substep, substepEnd); });
        }
        if (m_contact)
        {
            if (i == 0)
            {
                GuardStep first;
                first.time = substepEnd;
                first.dt = dt;
                first.substep = report.substep;
                first.integrator = m_settings.integrator;
                m_guard.checkSpeedBeforeContact(m_system, first);
            }
            m_contact->afterSubstep(m_system, m_context, report.substep);
            publishContact();
            m_guard.afterContact(m_system, m_settings.integrator);
        }
        runHooks([&](StepHook& hook) { hook.afterSubstep(m_system, m_context, report.substep, substepEnd); });
        if (hooksWriteExternalForces)
        {
            lookForExternalForces();
        }
    }
    m_substepCount += std::uint64_t(report.substeps);
    m_time += dt;
    if (m_contact)
    {
        m_contact->endFrame(m_system, m_context, m_time);
        publishContact();
    }
    runHooks([&](StepHook& hook) { hook.endFrame(m_system, m_context, m_time); });
    checkFinite(); // on every core; the guard's own finite check then only names the mass again
    GuardStep guarded;
    guarded.time = m_time;
    guarded.dt = dt;
    guarded.substep = report.substep;
    guarded.integrator = m_settings.integrator;
    guarded.contactForce = m_contact ? &m_contact->report().contactForce() : nullptr;
    m_guard.check(m_system, guarded);
    return report;
}

void Simulator::publishContact()
{
    // After every contact stage: the report's per-mass vector may have been resized by it.
    m_context.touchingObstacle = m_contact->report().touchingObstacle();
}

void Simulator::checkFinite() const
{
    // Each chunk checks its masses (a sum of every coordinate is non-finite if any is, and vectorises); the search
    // for the culprit below runs only on failure.
    const Particles& p = m_system.particles;
    std::vector<std::uint8_t> chunkFinite(chunkCount(p.size(), massChunkSize), 1);
    parallelFor(p.size(), massChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    Real sum = 0;
                    for (std::size_t i = begin; i < end; ++i)
                    {
                        sum += p.position[i].sum() + p.velocity[i].sum();
                    }
                    chunkFinite[begin / massChunkSize] = std::isfinite(sum) ? 1 : 0;
                });
    if (std::all_of(chunkFinite.begin(), chunkFinite.end(), [](std::uint8_t finite) { return finite != 0; }))
    {
        return;
    }
    for (std::size_t i = 0; i < p.size(); ++i)
    {
        if (!p.position[i].allFinite() || !p.velocity[i].allFinite())
        {
            throw NumericalError("the simulation diverged at t = " + formatNumber(m_time) + " s: mass " +
                                 std::to_string(i) + " has a non-finite position or velocity");
        }
    }
    throw NumericalError("the simulation diverged at t = " + formatNumber(m_time) +
                         " s: positions or velocities grew beyond the range of double precision");
}
} // namespace masse
