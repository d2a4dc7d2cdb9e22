#pragma once
/// Real time for a simulation whose step is fixed: wall time is banked each frame and spent in steps of the scene's
/// dt. Two caps keep a slow machine in slow motion instead of a spiral (each frame owing more than the last): the
/// wall time banked per frame is capped, and a frame that runs out of its compute budget forgets what it still owes.

#include "core/Types.h"

namespace masse::viewer
{
class StepScheduler
{
public:
    /// dt: the scene's step (s); maxFrameSeconds: the most wall time one frame may bank (a window drag or a scene
    /// load stalls the loop; the simulation should not then race to catch up).
    explicit StepScheduler(Real dt, Real maxFrameSeconds = Real(0.25));

    void setStep(Real dt);
    Real step() const { return m_dt; }

    /// Banks the wall time since the previous frame (capped at maxFrameSeconds).
    void addWallTime(Real seconds);
    bool stepDue() const { return m_owed >= m_dt; }
    void stepTaken();
    /// Called when a frame's compute budget ran out with steps still owed: the simulation falls behind real time
    /// (slow motion) rather than owing ever more.
    void forgetBacklog();
    /// Drops everything owed (pausing, rebuilding the scene).
    void clear() { m_owed = 0; }
    Real owed() const { return m_owed; }

private:
    Real m_dt;
    Real m_maxFrameSeconds;
    Real m_owed = 0;
};

/// Rates over a short window of wall time: frames drawn, steps and simulated seconds per wall second, for the HUD
/// and the benchmark. A new figure is published once per window so the numbers hold still long enough to read.
class RateMeter
{
public:
    explicit RateMeter(Real windowSeconds = Real(0.5)) : m_window(windowSeconds) {}

    /// One pass of the loop: wall seconds it took, frames drawn, steps taken, simulated seconds advanced, and
    /// whether it ran out of compute budget with steps still owed.
    void add(Real wallSeconds, int frames, int steps, Real simSeconds, bool behind = false);

    Real framesPerSecond() const { return m_fps; }
    Real stepsPerSecond() const { return m_sps; }
    /// Simulated seconds per wall second (1: real time; below: slow motion). Zero while nothing was simulated.
    Real realTimeFactor() const { return m_realTime; }
    bool hasFigures() const { return m_published; }
    /// Some pass of the last window ran out of budget: the simulation could not keep real time. (The factor alone
    /// cannot tell: a window holds a whole number of steps, so it wanders by a step's worth around 1.)
    bool fellBehind() const { return m_fellBehind; }

private:
    Real m_window;
    Real m_wall = 0;
    int m_frames = 0;
    int m_steps = 0;
    Real m_sim = 0;
    bool m_behind = false;
    Real m_fps = 0;
    Real m_sps = 0;
    Real m_realTime = 0;
    bool m_published = false;
    bool m_fellBehind = false;
};
} // namespace masse::viewer
