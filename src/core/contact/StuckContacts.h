#pragma once
/// Masses held by sticky contact: each sits at an anchor on its obstacle's surface and moves with that surface, until
/// the pull off the surface exceeds the release force. Per-mass state that lasts from frame to frame.

#include "core/contact/Contact.h"
#include "core/contact/ContactReport.h"
#include "core/lattice/Particles.h"

#include <algorithm>
#include <cstdint>
#include <vector>

namespace masse
{
struct StuckContacts
{
    std::vector<std::uint8_t> stuck;
    std::vector<Vec3> anchor;   ///< m, where the mass is held
    std::vector<Vec3> normal;   ///< the surface's normal there
    std::vector<Vec3> velocity; ///< m/s, the surface's velocity at the anchor this frame
    std::vector<int> obstacle;
    std::vector<int> face;
    bool any = false; ///< whether a mass has stuck since the run began (an empty set skips every loop over it)

    /// Sizes the arrays for `masses`, none stuck, if they are not that size already.
    void resize(std::size_t masses)
    {
        if (stuck.size() == masses)
        {
            return;
        }
        stuck.assign(masses, 0);
        anchor.assign(masses, Vec3::Zero());
        normal.assign(masses, Vec3::UnitY());
        velocity.assign(masses, Vec3::Zero());
        obstacle.assign(masses, -1);
        face.assign(masses, -1);
    }
    void releaseAll() { std::fill(stuck.begin(), stuck.end(), std::uint8_t(0)); }
    /// At a frame's start: each stuck mass's anchor moves with the point of its obstacle it is stuck to, as that point
    /// moves during the frame of dt.
    void followSurfaces(ContactDetector& detector, Real dt);
    /// After a substep of h: each stuck mass is released if the pull off its surface (its force along the normal)
    /// exceeds `releaseForce` (> 0), else carried with its anchor; the impulse that takes goes to `report`, with a
    /// touch at `time`.
    void hold(Particles& p, Real h, Real releaseForce, ContactReport& report, Real time);
    /// Holds mass i at `position` on the plane's surface.
    void stick(Index i, const Vec3& position, const ContactPlane& plane)
    {
        stuck[i] = 1;
        anchor[i] = position;
        normal[i] = plane.normal;
        velocity[i] = plane.velocity;
        obstacle[i] = plane.obstacle;
        face[i] = plane.face;
    }
};
} // namespace masse
