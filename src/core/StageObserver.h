#pragma once
/// The step's stage boundaries, for a profiler outside the core: the engine reads no clock itself (`masse bench`
/// times the frame's stages, the contact's and the implicit solve's through this; a program embedding the engine can
/// attach its own profiler the same way). Stages do not nest within themselves; the implicit solve's lie within the
/// integrator's step.

#include "core/StepStage.h"

#include <type_traits>

namespace masse
{
enum class Stage
{
    ContactDetection,     ///< finding every mass's planes with the detector, once per frame
    ContactProjection,    ///< applying the planes after every substep
    ContactSweep,         ///< the end-of-frame sweep and reports
    SelfContactPairs,     ///< the sheet's self-contact broadphase: each frame's start and when a mass outruns its skin
    SelfContactSolve,     ///< the sheet's self-contact narrowphase and response after every substep
    EdgeContactPairs,     ///< listing the sheet's edges and triangles near obstacle edges and corners
    EdgeContactSolve,     ///< their narrowphase and response after every substep
    SolverAnalysis,       ///< the implicit solve's matrix pattern, ordering and factor analysis, once per topology
    SolverAssembly,       ///< each solve's matrix and right-hand side, and its constraints' filter
    SolverPreconditioner, ///< refactorisations of the preconditioner, and its following of the diagonal between them
    SolverIterations,     ///< the conjugate gradient's iterations
};

inline constexpr int stageCount = 11;

class StageObserver
{
public:
    virtual ~StageObserver() = default;
    virtual void begin(Stage stage) = 0;
    virtual void end(Stage stage) = 0;
    /// A stage of the frame's table (StepStage.h) begins or ends: the Simulator's own work and its hooks' in it. The
    /// stages above lie within these (the solve's within `integrate`, the obstacle contact's within its stages).
    virtual void beginStep(StepStage /*stage*/) {}
    virtual void endStep(StepStage /*stage*/) {}
};

/// Tells an observer (if any) that a stage runs for the lifetime of this object: a profiler's Stage, or a StepStage of
/// the frame's table.
template <class Kind> class ObservedStage
{
public:
    ObservedStage(StageObserver* observer, Kind stage) : m_observer(observer), m_stage(stage)
    {
        if (m_observer)
        {
            notify(true);
        }
    }
    ~ObservedStage()
    {
        if (m_observer)
        {
            notify(false);
        }
    }
    ObservedStage(const ObservedStage&) = delete;
    ObservedStage& operator=(const ObservedStage&) = delete;

private:
    void notify(bool begins)
    {
        if constexpr (std::is_same_v<Kind, StepStage>)
        {
            begins ? m_observer->beginStep(m_stage) : m_observer->endStep(m_stage);
        }
        else
        {
            begins ? m_observer->begin(m_stage) : m_observer->end(m_stage);
        }
    }

    StageObserver* m_observer;
    Kind m_stage;
};
using StageScope = ObservedStage<Stage>;
using StepStageScope = ObservedStage<StepStage>;
} // namespace masse
