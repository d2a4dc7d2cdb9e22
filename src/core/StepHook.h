#pragma once
/// A model that advances alongside the mechanics (heat, material state, loads, scripts, the three contacts): it joins
/// named stages of the frame (StepStage.h) and the Simulator calls it at those, hooks in the order added within a
/// stage. What a hook needs from another stage it reads from the StepContext (StepContext.h says who publishes what),
/// never through a pointer into another model.
///
/// A hook says which stages it joins (stages()) and is called through run(). The default run() hands the five stages
/// most models join to the functions named after them below, so a model overrides those and lists them in stages();
/// a hook that joins other stages (the obstacle contact joins the three contact stages) overrides run() itself.

#include "core/MassSpringSystem.h"
#include "core/StepContext.h"
#include "core/StepStage.h"

namespace masse
{
class StepHook
{
public:
    virtual ~StepHook() = default;
    /// The stages the Simulator calls this hook at. The default: the five stages of the functions below.
    virtual StageSet stages() const
    {
        return {StepStage::BeforeFrame, StepStage::BeginFrame, StepStage::AfterSolve, StepStage::AfterSubstep,
                StepStage::EndFrame};
    }
    /// One stage of the frame: hands the five named stages to the functions below.
    virtual void run(StepStage stage, const StageCall& call)
    {
        switch (stage)
        {
        case StepStage::BeforeFrame:
            beforeFrame(call.system, call.context, call.time);
            break;
        case StepStage::BeginFrame:
            beginFrame(call.system, call.context, call.time, call.plan.dt);
            break;
        case StepStage::AfterSolve:
            afterImplicitSolve(call.system, call.context, call.plan.substep, call.time);
            break;
        case StepStage::AfterSubstep:
            afterSubstep(call.system, call.context, call.plan.substep, call.time);
            break;
        case StepStage::EndFrame:
            endFrame(call.system, call.context, call.time);
            break;
        default:
            break;
        }
    }
    /// With one solve a frame (FramePlan::oneSolveAFrame), before anything else of a frame of length dt: into how
    /// many frames of dt / n, each with all its stages, the hook asks the Simulator to split it (the largest ask
    /// wins). For motion that one solve of dt cannot follow: the self-contact asks when its pairs close fast.
    virtual int solvesFor(MassSpringSystem& /*system*/, Real /*dt*/) { return 1; }
    /// After each solve of a split frame, which took `taken` seconds, with `rest` of the frame still to go: into how
    /// many solves the hook now asks for the rest to be split, or 0 to keep the frame's split as it was. For a hook
    /// whose count for the frame was a guess (the motion limit's first frame, with no motion yet to go by), which the
    /// frame's first solves then tell it how to correct. The Simulator takes the next solve of rest / count and asks
    /// again.
    virtual int solvesForRest(MassSpringSystem& /*system*/, Real /*taken*/, Real /*rest*/) { return 0; }

    /// beforeFrame: at a frame's very start, before the stability estimate and contact detection, so that what it
    /// changes (a pin released, a grab's spring, an obstacle moved) is seen by both in this frame: script actions.
    virtual void beforeFrame(MassSpringSystem& /*system*/, StepContext& /*context*/, Real /*time*/) {}
    /// beginFrame: before the first substep of a frame from `time` to `time + dt`, after contact detection.
    virtual void beginFrame(MassSpringSystem& /*system*/, StepContext& /*context*/, Real /*time*/, Real /*dt*/) {}
    /// afterSolve: with an implicit integrator (one solve a frame), after the solve and before the obstacle contact's
    /// projection, so that the projection can put back what the hook pushed into an obstacle: no later substep would.
    /// With the step's length and the time at its end.
    virtual void afterImplicitSolve(MassSpringSystem& /*system*/, StepContext& /*context*/, Real /*h*/, Real /*time*/)
    {
    }
    /// afterSubstep: after each substep of length h (and after the obstacle projection), with the time at its end.
    virtual void afterSubstep(MassSpringSystem& /*system*/, StepContext& /*context*/, Real /*h*/, Real /*time*/) {}
    /// endFrame: after the last substep (and after the contact report), with the time at the end of the frame.
    virtual void endFrame(MassSpringSystem& /*system*/, StepContext& /*context*/, Real /*time*/) {}

    /// Whether afterSubstep may write particles.externalForce. The Simulator then looks at them again after every
    /// substep's hooks, not only at a frame's start (SubstepHints::externalForces); a hook that writes them without
    /// saying so may go unfelt until the next frame.
    virtual bool writesExternalForcesMidFrame() const { return false; }
    /// Whether a stage after this substep reads particles.force (the forces of the substep just taken). Else they
    /// are only kept at a frame's last substep (SubstepHints::forcesRead), and it may find those of an earlier one.
    /// Asked before every substep.
    virtual bool readsForcesMidFrame() const { return false; }
};
} // namespace masse
