#pragma once
/// The rest rule of a run (`run.stop_at_rest`): the sheet rests once its kinetic energy has stayed below a threshold
/// for a hold time, counted only while the run is ready for rest (its script done, every scripted motion ended, and
/// the obstacles it must touch first touched). One rule for the scene and for the comparison's Bullet twins, so both
/// engines' "rest" events mean the same thing.

#include "core/Types.h"

namespace masse::scene
{
class RestTracker
{
public:
    RestTracker() = default;
    /// `kineticEnergyBelow` in J, `hold` in s.
    RestTracker(Real kineticEnergyBelow, Real hold) : m_threshold(kineticEnergyBelow), m_hold(hold) {}

    /// One frame ending at `time`, with the sheet's kinetic energy (read only when `ready`). Returns true on the one
    /// frame the sheet is first found at rest; since() then says from when.
    bool update(Real time, Real kineticEnergy, bool ready);

    /// Whether the energy has stayed low for the hold time by `time`.
    bool atRest(Real time) const { return m_since >= 0 && time - m_since >= m_hold - 1e-9; }
    /// Whether the sheet has been found at rest in this run.
    bool rested() const { return m_rested; }
    /// s, since when the energy has stayed low (-1: it is not low now).
    Real since() const { return m_since; }

private:
    Real m_threshold = 0;
    Real m_hold = 0;
    Real m_since = -1;
    bool m_rested = false;
};
} // namespace masse::scene
