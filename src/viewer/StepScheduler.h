#pragma once
/// Real time for a simulation whose step is fixed: wall time is banked each pass of the loop and spent in steps of
/// the scene's dt. A pass steps only within its compute budget and leaves the rest owed, so a passing hiccup (a
/// slow frame) is caught up over the next passes; what is owed is capped, so a machine too slow for real time runs
/// in slow motion instead of a spiral (each pass owing more than the last).

#include "core/Types.h"

namespace masse::viewer
{
class StepScheduler
{
public:
    /// dt: the scene's step (s); maxLag: the most wall time the simulation may owe (s). Beyond it, time is dropped:
    /// a window drag or a scene load stalls the loop, and the simulation should not then race to catch up.
    explicit StepScheduler(Real dt, Real maxLag = Real(0.25));

    void setStep(Real dt);
    Real step() const { return m_dt; }

    /// Banks wall time; returns true when some was dropped at the cap (the simulation fell behind real time).
    bool addWallTime(Real seconds);
    bool stepDue() const { return m_owed >= m_dt; }
    void stepTaken();
    /// Drops everything owed (pausing, rebuilding the scene).
    void clear() { m_owed = 0; }
    Real owed() const { return m_owed; }

private:
    Real m_dt;
    Real m_maxLag;
    Real m_owed = 0;
};

/// Rates over a short window of wall time: frames drawn, steps and simulated seconds per wall second, for the HUD
/// and the benchmark. A new figure is published once per window so the numbers hold still long enough to read.
class RateMeter
{
public:
    explicit RateMeter(Real windowSeconds = Real(0.5)) : m_window(windowSeconds) {}

    /// One pass of the loop: wall seconds it took, frames drawn, steps taken, simulated seconds advanced, and
    /// whether time owed to the simulation was dropped (it could not keep real time).
    void add(Real wallSeconds, int frames, int steps, Real simSeconds, bool behind = false);

    Real framesPerSecond() const { return m_fps; }
    Real stepsPerSecond() const { return m_sps; }
    /// Simulated seconds per wall second (1: real time; below: slow motion). Zero while nothing was simulated.
    Real realTimeFactor() const { return m_realTime; }
    bool hasFigures() const { return m_published; }
    /// Some pass of the last window dropped owed time: the simulation could not keep real time. (The factor alone
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
