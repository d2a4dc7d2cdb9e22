#pragma once
/// The contact's per-substep kernel: each mass of a range is projected out of its planes and its approach velocity
/// removed, with the response of the plane's obstacle (sticky, Coulomb friction, frictionless). A call touches only
/// the state of the masses in its range, so ranges run on any thread; first touches of an obstacle go to the range's
/// own list, recorded afterwards in range order.

#include "ContactConstraints.h"
#include "ContactPlanes.h"
#include "ContactReport.h"
#include "StuckContacts.h"

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
    ContactReport& report;
    Real elapsed; ///< s since the frame began (kinematic surfaces have moved by their velocity times this)
    Real h;       ///< the substep just taken

    /// Projects masses [begin, end); obstacles touched for the first time go to `firstTouches`; `madeStuck` is set if
    /// a mass stuck.
    void run(std::size_t begin, std::size_t end, std::vector<int>& firstTouches, bool& madeStuck) const;

private:
    void projectMass(Index i, std::vector<int>& firstTouches, bool& madeStuck) const;
};
} // namespace masse
