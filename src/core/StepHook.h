#pragma once
/// A model that advances alongside the mechanics (heat, material state, loads, scripts): the Simulator calls it around
/// every frame and after every integrator substep, after the contact solver. Hooks run in the order added; what a
/// hook needs from another stage it reads from the StepContext (StepContext.h says who publishes what), never through
/// a pointer into another model.

#include "core/MassSpringSystem.h"
#include "core/StepContext.h"

namespace masse
{
class StepHook
{
public:
    virtual ~StepHook() = default;
    /// At a frame's very start, before the stability estimate and contact detection, so that what it changes (a pin
    /// released, a grab's spring, an obstacle moved) is seen by both in this frame: the place for script actions.
    virtual void beforeFrame(MassSpringSystem& /*system*/, StepContext& /*context*/, Real /*time*/) {}
    /// With one solve a frame (StepContext::oneSolveAFrame), before anything else of a frame of length dt: into how
    /// many frames of dt / n, each with all its stages, the hook asks the Simulator to split it (the largest ask
    /// wins). For motion that one solve of dt cannot follow: the self-contact asks when its pairs close fast.
    virtual int solvesFor(MassSpringSystem& /*system*/, Real /*dt*/) { return 1; }
    /// Before the first substep of a frame from `time` to `time + dt`.
    virtual void beginFrame(MassSpringSystem& /*system*/, StepContext& /*context*/, Real /*time*/, Real /*dt*/) {}
    /// With an implicit integrator (one solve a frame), after the solve and before the obstacle contact's
    /// projection, so that the projection can put back what the hook pushed into an obstacle: no later substep would.
    /// With the step's length and the time at its end.
    virtual void afterImplicitSolve(MassSpringSystem& /*system*/, StepContext& /*context*/, Real /*h*/, Real /*time*/)
    {
    }
    /// After each substep of length h (and after contact), with the time at its end.
    virtual void afterSubstep(MassSpringSystem& /*system*/, StepContext& /*context*/, Real /*h*/, Real /*time*/) {}
    /// After the last substep (and after contact's end of frame), with the time at the end of the frame.
    virtual void endFrame(MassSpringSystem& /*system*/, StepContext& /*context*/, Real /*time*/) {}
    /// Whether afterSubstep may write particles.externalForce. The Simulator then looks at them again after every
    /// substep's hooks, not only at a frame's start (see StepContext::externalForces); a hook that writes them
    /// without saying so may go unfelt until the next frame.
    virtual bool writesExternalForcesMidFrame() const { return false; }
    /// Whether afterSubstep reads particles.force (the forces of the substep just taken). Else they are only kept at
    /// a frame's last substep (see StepContext::forcesRead), and afterSubstep may find those of an earlier one.
    virtual bool readsForcesMidFrame() const { return false; }
};
} // namespace masse
