#pragma once
/// The step's stage boundaries, for a profiler outside the core: the engine reads no clock itself (`masse bench`
/// times the contact stages and the implicit solve's through this; a program embedding the engine can attach its own
/// profiler the same way). Stages do not nest within themselves; the implicit solve's lie within the integrator's step.

#include "core/StepStage.h"

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

/// Tells an observer (if any) that a stage of the frame's table runs for the lifetime of this object.
class StepStageScope
{
public:
    StepStageScope(StageObserver* observer, StepStage stage) : m_observer(observer), m_stage(stage)
    {
        if (m_observer)
        {
            m_observer->beginStep(m_stage);
        }
    }
    ~StepStageScope()
    {
        if (m_observer)
        {
            m_observer->endStep(m_stage);
        }
    }
    StepStageScope(const StepStageScope&) = delete;
    StepStageScope& operator=(const StepStageScope&) = delete;

private:
    StageObserver* m_observer;
    StepStage m_stage;
};

/// Tells an observer (if any) that a stage runs for the lifetime of this object.
class StageScope
{
public:
    StageScope(StageObserver* observer, Stage stage) : m_observer(observer), m_stage(stage)
    {
        if (m_observer)
        {
            m_observer->begin(m_stage);
        }
    }
    ~StageScope()
    {
        if (m_observer)
        {
            m_observer->end(m_stage);
        }
    }
    StageScope(const StageScope&) = delete;
    StageScope& operator=(const StageScope&) = delete;

private:
    StageObserver* m_observer;
    Stage m_stage;
};
} // namespace masse
