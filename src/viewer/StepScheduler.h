#pragma once
/// Real time for a simulation whose step is fixed: wall time is banked each pass of the loop and spent in steps of
/// the scene's dt. A pass steps only within its compute budget and leaves the rest owed, so a passing hiccup (a
/// slow frame) is caught up over the next passes; what is owed is capped, so a machine too slow for real time runs
/// in slow motion instead of a spiral (each pass owing more than the last).
///
/// The cap is a second, longer than the hiccups of a forming scene that otherwise keeps real time: its first frame
/// analyses the implicit solver's pattern and meets the mould in many short solves (0.6 s for the 64x2x64 vacuum cup,
/// whose later frames take some 17 ms of their 30), and a refactorisation at 128x2x128 takes a quarter of a second.
/// Such a hiccup is caught up, so the scene keeps to the wall clock.

#include "core/Types.h"

namespace masse::viewer
{
class StepScheduler
{
public:
    /// dt: the scene's step (s); maxLag: the most wall time the simulation may owe (s). Beyond it, time is dropped:
    /// the machine cannot keep real time, and the scene runs in slow motion.
    explicit StepScheduler(Real dt, Real maxLag = Real(1));

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
