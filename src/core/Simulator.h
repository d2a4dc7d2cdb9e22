#pragma once
/// Advances a sheet in time: splits each requested step into stable substeps for the explicit integrators, runs the
/// frame's stages in the order of one table (StepStage.h) with the models that joined them (StepHook.h), keeps the
/// clock, and refuses to go on silently with a non-finite state. Its kernels run on a task pool of its own, or one
/// it is given: nothing in the engine is shared between simulators unless their program shares it.

#include "core/DivergenceGuard.h"
#include "core/NumericalError.h"
#include "core/StepHook.h"
#include "core/contact/ContactSolver.h"
#include "core/integrate/Integrator.h"
#include "core/integrate/SolverTally.h"
#include "core/integrate/StabilityEstimate.h"
#include "core/parallel/TaskPool.h"

#include <array>
#include <memory>
#include <stdexcept>

namespace masse
{
struct SimulatorSettings
{
    IntegratorKind integrator = IntegratorKind::ImplicitEuler;
    ImplicitSettings implicit;
    Real stabilitySafety = 0.5; ///< fraction of the estimated stable step the explicit integrators take
    int maxSubsteps = 100000;   ///< per step; beyond it the step is refused with a message (use the implicit one)
    /// How the explicit integrators' stable step is estimated; the power estimate is tight, Gershgorin's bound safe.
    StabilityMethod stabilityMethod = StabilityMethod::Power;
    /// Threads of the simulator's own pool, the calling thread included (1 to maxThreadCount): the same bits at any
    /// count. Unused when the simulator is given a pool.
    int threads = 1;
};

/// What one call to Simulator::step did.
struct StepReport
{
    int substeps = 0;
    Real substep = 0;         ///< s
    int solverIterations = 0; ///< summed over substeps (implicit only)
    Real solverResidual = 0;  ///< worst over substeps (implicit only)
    int solverCapHits = 0;    ///< substeps whose solve stopped at the iteration cap (implicit only)
};

class Simulator
{
public:
    /// Throws InputError for field "threads" when settings.threads is out of range or the threads cannot start.
    Simulator(MassSpringSystem system, const SimulatorSettings& settings);
    /// Runs its kernels on `pool` (not null), which several simulators may share: a pool runs one loop at a time, and
    /// a simulator stepping while another uses it runs its loops on its own thread (the same bits).
    Simulator(MassSpringSystem system, const SimulatorSettings& settings, std::shared_ptr<TaskPool> pool);

    /// Advances by dt seconds (dt > 0). Throws InputError for a bad dt or one that would need more than maxSubsteps,
    /// NumericalError if the guard finds the state unsound (non-finite, too fast, energy from nowhere). With one
    /// solve a frame, a hook may ask for the frame to be taken as several (StepHook::solvesFor); the report then
    /// sums their substeps and iterations.
    StepReport step(Real dt);

    /// Number of substeps step(dt) would take now.
    int substepsFor(Real dt) const;

    MassSpringSystem& system() { return m_system; }
    const MassSpringSystem& system() const { return m_system; }
    /// What the frame's stages hand one another (the contact's velocity constraints). Its constraints are cleared at
    /// each frame's start, before the hooks that set them (the contact solver, the self-contact) run.
    StepContext& context() { return m_context; }
    const SimulatorSettings& settings() const { return m_settings; }
    void setIntegrator(IntegratorKind kind);
    /// Reports the integrator's stages (the implicit solve's, StageObserver.h) to `observer`, which must outlive its
    /// use here, or to none with nullptr; kept across setIntegrator.
    void setStageObserver(StageObserver* observer);
    /// Contact with obstacles (the three contact stages), replacing any earlier one; nullptr for none. The solver must
    /// outlive its use here. Its report's contact forces are the guard's.
    void setContactSolver(ContactSolver* contact);
    /// Models advanced with the mechanics (see StepHook.h): called at the stages hook->stages() names, in the order
    /// added within a stage. Each must outlive its use here.
    void addHook(StepHook* hook);
    Real time() const { return m_time; }
    /// The pool its kernels run on. A program that calls kernels between steps (a report, an energy) binds it with a
    /// PoolScope to run them on the same threads.
    TaskPool& pool() const { return *m_pool; }
    int threadCount() const { return m_pool->threadCount(); }
    /// Replaces the pool by one of its own of `threads` threads (see SimulatorSettings::threads); between steps only.
    void setThreadCount(int threads);
    /// The divergence guard run after every step (its bounds come from the scene).
    DivergenceGuard& guard() { return m_guard; }
    std::uint64_t substepCount() const { return m_substepCount; }
    /// The implicit solver's statistics since construction (empty for the explicit integrators).
    const SolverTally& solverTally() const { return m_solverTally; }

private:
    /// A frame under way: its plan and what it reports.
    struct Frame
    {
        FramePlan plan;
        StepReport report;
        bool substepsDone = false;
        bool hooksWriteExternalForces = false; ///< some hook writes external forces after a substep
    };
    /// One frame of dt with every stage: what step does when no hook asks for more solves. Walks stepStageTable.
    StepReport stepFrame(Real dt);
    /// One stage of the frame: its hooks, and what the Simulator itself does there (the plan, the integrator, the
    /// checks); the one place the divergence guard is told of stage boundaries.
    void runStage(StepStage stage, Frame& frame);
    void runHooks(StepStage stage, const Frame& frame);
    void integrate(Frame& frame);
    /// Looks whether every external force is +0 (SubstepHints::externalForces); only the symplectic pass reads it.
    void lookForExternalForces(Frame& frame) const;
    void checkFinite() const;
    /// The stability estimate, recomputed only when the system changed (its revision) or the repulsion makes it
    /// depend on the current spring lengths.
    const StabilityEstimate& stability() const;

    MassSpringSystem m_system;
    StepContext m_context;
    SimulatorSettings m_settings;
    std::shared_ptr<TaskPool> m_pool;
    std::unique_ptr<Integrator> m_integrator;
    StageObserver* m_observer = nullptr; ///< the integrator's, kept across setIntegrator
    ContactSolver* m_contact = nullptr;
    std::vector<StepHook*> m_hooks; ///< every hook, the contact solver among them, in the order added
    std::vector<int> m_solvesAsked; ///< per hook, the solves it asked for the frame being split (step)
    std::array<std::vector<StepHook*>, stepStageCount> m_stageHooks; ///< per stage, the hooks that joined it
    DivergenceGuard m_guard;
    Real m_time = 0;
    std::uint64_t m_substepCount = 0;
    SolverTally m_solverTally;
    mutable StabilityEstimate m_stability;
    mutable std::uint64_t m_stabilityRevision = ~std::uint64_t(0);
};
} // namespace masse
