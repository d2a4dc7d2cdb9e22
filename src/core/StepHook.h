#pragma once
/// A model that advances alongside the mechanics (heat, material state): the Simulator calls it around every frame
/// and after every integrator substep, after the contact solver.

#include "MassSpringSystem.h"

namespace masse
{
class StepHook
{
public:
    virtual ~StepHook() = default;
    /// Before the first substep of a frame from `time` to `time + dt`.
    virtual void beginFrame(MassSpringSystem& /*system*/, Real /*time*/, Real /*dt*/) {}
    /// After each substep of length h (and after contact), with the time at its end.
    virtual void afterSubstep(MassSpringSystem& /*system*/, Real /*h*/, Real /*time*/) {}
    /// After the last substep (and after contact's end of frame), with the time at the end of the frame.
    virtual void endFrame(MassSpringSystem& /*system*/, Real /*time*/) {}
};
} // namespace masse
