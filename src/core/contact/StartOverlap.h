#pragma once
/// Masses that start on or within the contact radius of a surface (a sheet laid on a box whose top is at its bottom
/// layer): each may stay as deep as it starts, so the contact holds it where it was placed. Pushed out to the radius
/// within the first substep instead, the bottom layer would squeeze the layer springs by up to the radius and the
/// sheet would leave the surface at a metre a second or more. The depth a mass may keep only shrinks, as the mass
/// moves out, and is gone once it has left the radius; masses that start clear of every surface never have one.

#include "core/contact/ContactPlanes.h"
#include "core/lattice/Particles.h"

#include <vector>

namespace masse
{
struct StartOverlap
{
    std::vector<Real> depth; ///< m, in [0, radius]: how far within the radius of its planes mass i may stay
    bool any = false;        ///< whether some mass has a depth (else no loop reads `depth`)

    /// At each frame's start, once the planes are found. On the contact's first frame each free mass gets the depth
    /// its planes have it at within the radius, if its centre is not behind a surface (a mass inside an obstacle is
    /// pushed out as ever); on later frames a mass keeps the least of that depth and the one it had.
    void update(const Particles& p, const ContactPlanes& planes, Real radius);

private:
    bool m_started = false;
    std::vector<Real> m_next;
};
} // namespace masse
