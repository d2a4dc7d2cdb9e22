#pragma once
/// The contact's per-substep kernel: each mass of a range is projected out of its planes and its approach velocity
/// removed, with the response of the plane's obstacle (sticky, Coulomb friction, frictionless). A call touches only
/// the state of the masses in its range, so ranges run on any thread; first touches of an obstacle go to the range's
/// own list, recorded afterwards in range order.

#include "core/contact/ContactConstraints.h"
#include "core/contact/ContactPlanes.h"
#include "core/contact/ContactReport.h"
#include "core/contact/StartOverlap.h"
#include "core/contact/StuckContacts.h"

#include <vector>

namespace masse
{
/// What the projection reads and writes.
struct ContactProjection
{
    Particles& particles;
    const ContactPlanes& planes;
    const ContactSettings& settings;
    const ContactConstraints& constraints; ///< resting masses are only mended, not projected
    StuckContacts& stuck;
    const StartOverlap& startOverlap; ///< masses that may stay as deep within the radius as they started
    ContactReport& report;
    Real elapsed; ///< s since the frame began (kinematic surfaces have moved by their velocity times this)
    /// s: how far a velocity change moves a mass after the substep just taken (StepContext::moveStep: the
    /// substep, or BDF2's 2h/3)
    Real moveStep;

    /// Projects the masses of entries [begin, end) of planes' list of masses with planes (a range within one of its
    /// runs of ContactPlanes::runLength); obstacles touched for the first time go to `firstTouches`; `madeStuck` is
    /// set if a mass stuck.
    void run(std::size_t begin, std::size_t end, std::vector<int>& firstTouches, bool& madeStuck) const;

private:
    /// Entry j's mass through its planes, one at a time. Still: every plane's surface velocity is +0 (read as a
    /// constant, the same bits). Constrained: some masses rest or arrive in the implicit solve this frame (else the
    /// per-mass flags are all clear and go unread).
    template <bool Still, bool Constrained>
    [[gnu::always_inline]] inline void projectEntry(std::size_t j, std::vector<int>& firstTouches,
                                                    bool& madeStuck) const;
    template <bool Still, bool Constrained>
    void projectRange(std::size_t begin, std::size_t end, std::vector<int>& firstTouches, bool& madeStuck) const;
};
} // namespace masse
