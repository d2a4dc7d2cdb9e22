#pragma once
/// What the HUD and the benchmark report of the loop's speed.

#include "core/Types.h"

namespace masse::viewer
{
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
