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
    m_integrator->setStageObserver(m_observer);
    m_system.markChanged();
}

void Simulator::setStageObserver(StageObserver* observer)
{
    m_observer = observer;
    m_integrator->setStageObserver(observer);
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
    if (!isExplicit(m_settings.integrator))
    {
        // An implicit step is stable at any length: the estimate, a pass over every spring, would not change this.
        return 1;
    }
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
    m_solvesAsked.resize(m_hooks.size());
    for (std::size_t h = 0; h < m_hooks.size(); ++h)
    {
        m_solvesAsked[h] = std::max(1, m_hooks[h]->solvesFor(m_system, dt));
        solves = std::max(solves, m_solvesAsked[h]);
    }
    if (solves == 1)
    {
        return stepFrame(dt);
    }
    StepReport report;
    Real length = dt / Real(solves);
    Real rest = dt;
    for (int left = solves; left > 0;)
    {
        const StepReport part = stepFrame(length);
        report.substeps += part.substeps;
        report.substep = part.substep;
        report.solverIterations += part.solverIterations;
        report.solverResidual = std::max(report.solverResidual, part.solverResidual);
        report.solverCapHits += part.solverCapHits;
        rest -= length;
        if (--left == 0)
        {
            break;
        }
        // A hook that guessed the frame's split corrects it for the rest; the others keep the length they asked for.
        int asked = 0;
        Real longest = rest;
        for (std::size_t h = 0; h < m_hooks.size(); ++h)
        {
            const int count = m_hooks[h]->solvesForRest(m_system, length, rest);
            asked = std::max(asked, count);
            if (count == 0)
            {
                longest = std::min(longest, dt / Real(m_solvesAsked[h]));
            }
        }
        if (asked > 0)
        {
            left = std::max(asked, int(std::ceil(rest / longest)));
            length = rest / Real(left);
        }
    }
    return report;
}

void Simulator::addHook(StepHook* hook)
{
    m_hooks.push_back(hook);
    const StageSet joined = hook->stages();
    for (const StepStageEntry& entry : stepStageTable)
    {
        if (entry.hooksJoin && joined.contains(entry.stage))
        {
            m_stageHooks[int(entry.stage)].push_back(hook);
        }
    }
}

void Simulator::setContactSolver(ContactSolver* contact)
{
    if (m_contact)
    {
        const auto without = [this](std::vector<StepHook*>& hooks) { std::erase(hooks, m_contact); };
        without(m_hooks);
        for (std::vector<StepHook*>& hooks : m_stageHooks)
        {
            without(hooks);
        }
    }
    m_contact = contact;
    if (m_contact)
    {
        addHook(m_contact);
    }
}

StepReport Simulator::stepFrame(Real dt)
{
    Frame frame;
    frame.plan.start = m_time;
    frame.plan.dt = dt;
    // The table's once-a-frame stages in order; at its run of every-substep stages, that run once per substep.
    for (int k = 0; k < stepStageCount;)
    {
        if (!stepStageTable[k].everySubstep)
        {
            runStage(stepStageTable[k].stage, frame);
            ++k;
            continue;
        }
        int end = k;
        while (end < stepStageCount && stepStageTable[end].everySubstep)
        {
            ++end;
        }
        for (int i = 0; i < frame.plan.substeps; ++i)
        {
            frame.plan.substepIndex = i;
            for (int j = k; j < end; ++j)
            {
                runStage(stepStageTable[j].stage, frame);
            }
        }
        m_substepCount += std::uint64_t(frame.plan.substeps);
        m_time += dt; // the stages after the substeps stand at the frame's end
        frame.substepsDone = true;
        k = end;
    }
    return frame.report;
}

void Simulator::runHooks(StepStage stage, const Frame& frame)
{
    const Real time = frame.substepsDone               ? m_time
                      : stageEntry(stage).everySubstep ? frame.plan.substepEnd()
                                                       : frame.plan.start;
    const StageCall call{m_system, m_context, frame.plan, time};
    for (StepHook* hook : m_stageHooks[int(stage)])
    {
        hook->run(stage, call);
    }
}

void Simulator::runStage(StepStage stage, Frame& frame)
{
    const StepStageScope timed(m_observer, stage);
    FramePlan& plan = frame.plan;
    const bool hooksHere = !m_stageHooks[int(stage)].empty();
    switch (stage)
    {
    case StepStage::PlanFrame:
        plan.substeps = substepsFor(plan.dt);
        plan.substep = plan.dt / Real(plan.substeps);
        plan.oneSolveAFrame = !isExplicit(m_settings.integrator);
        plan.constrain = m_integrator->honoursConstraints();
        frame.report.substeps = plan.substeps;
        frame.report.substep = plan.substep;
        m_context.constraints.clear(); // the contact solver clears them too; without one, the self-contact's are here
        return;
    case StepStage::Integrate:
        m_guard.beforeSubstep(m_system, m_settings.integrator);
        integrate(frame);
        m_guard.afterIntegrator(m_system, m_settings.integrator);
        return;
    case StepStage::AfterSolve:
        if (!plan.oneSolveAFrame)
        {
            return; // the explicit integrators' substeps have no solve to follow
        }
        break;
    case StepStage::ContactProjection:
        if (hooksHere && plan.substepIndex == 0)
        {
            // A solve that went wrong is named before the contact's projection hides it.
            GuardStep first;
            first.time = plan.substepEnd();
            first.dt = plan.dt;
            first.substep = plan.substep;
            first.integrator = m_settings.integrator;
            m_guard.checkSpeedBeforeContact(m_system, first);
        }
        runHooks(stage, frame);
        if (hooksHere)
        {
            m_guard.afterContact(m_system, m_settings.integrator);
        }
        return;
    case StepStage::Check:
    {
        checkFinite(); // on every core; the guard's own finite check then only names the mass again
        GuardStep guarded;
        guarded.time = m_time;
        guarded.dt = plan.dt;
        guarded.substep = plan.substep;
        guarded.integrator = m_settings.integrator;
        guarded.contactForce = m_contact ? &m_contact->report().contactForce() : nullptr;
        m_guard.check(m_system, guarded);
        return;
    }
    default:
        break;
    }
    // The hook stages. Around those of the models the guard accounts for the energy they put in or take out.
    const bool accountEnergy = stageEntry(stage).guardAccountsEnergy;
    if (accountEnergy)
    {
        m_guard.beforeHooks(m_system);
    }
    runHooks(stage, frame);
    if (accountEnergy)
    {
        m_guard.afterHooks(m_system);
    }
    if (stage == StepStage::BeginFrame)
    {
        lookForExternalForces(frame);
        frame.hooksWriteExternalForces = std::any_of(
            m_hooks.begin(), m_hooks.end(), [](const StepHook* hook) { return hook->writesExternalForcesMidFrame(); });
    }
    else if (stage == StepStage::AfterSubstep && frame.hooksWriteExternalForces)
    {
        lookForExternalForces(frame);
    }
}

void Simulator::integrate(Frame& frame)
{
    FramePlan& plan = frame.plan;
    plan.hints.forcesRead =
        plan.substepIndex + 1 == plan.substeps ||
        std::any_of(m_hooks.begin(), m_hooks.end(), [](const StepHook* hook) { return hook->readsForcesMidFrame(); });
    m_context.moveStep = plan.substep;
    const IntegratorStats stats = m_integrator->step(m_system, m_context, plan.substep, plan.hints);
    StepReport& report = frame.report;
    report.solverIterations += stats.solverIterations;
    report.solverResidual = std::max(report.solverResidual, stats.solverResidual);
    report.solverCapHits += stats.hitIterationCap ? 1 : 0;
    if (!isExplicit(m_settings.integrator))
    {
        m_solverTally.add(stats);
    }
}

void Simulator::lookForExternalForces(Frame& frame) const
{
    // Only the symplectic pass skips zero external forces; the hooks may write them (a pressure load does).
    frame.plan.hints.externalForces =
        m_settings.integrator != IntegratorKind::SymplecticEuler || !noExternalForces(m_system.particles);
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
