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

} // namespace masse::viewer
