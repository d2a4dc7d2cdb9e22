#include "ContactProjection.h"

#include <algorithm>
#include <cmath>

namespace masse
{
void ContactProjection::run(std::size_t begin, std::size_t end, std::vector<int>& firstTouches, bool& madeStuck) const
{
    const bool still = planes.stillRun(begin / ContactPlanes::runLength);
    const bool constrained = constraints.any();
    if (still && !constrained)
    {
        projectRange<true, false>(begin, end, firstTouches, madeStuck);
    }
    else if (still)
    {
        projectRange<true, true>(begin, end, firstTouches, madeStuck);
    }
    else if (!constrained)
    {
        projectRange<false, false>(begin, end, firstTouches, madeStuck);
    }
    else
    {
        projectRange<false, true>(begin, end, firstTouches, madeStuck);
    }
}

template <bool Still, bool Constrained>
void ContactProjection::projectRange(std::size_t begin, std::size_t end, std::vector<int>& firstTouches,
                                     bool& madeStuck) const
{
    for (std::size_t j = begin; j < end; ++j)
    {
        projectEntry<Still, Constrained>(j, firstTouches, madeStuck);
    }
}

// The arithmetic is spelt out per coordinate, in the order Eigen's 3-vector operations take (a dot product sums
// (x + y) + z): the same bits as the vector form, in about a third fewer instructions than Eigen's two-and-one split
// of a 3-vector into SSE2 registers, which is what this kernel's time went to.
template <bool Still, bool Constrained>
void ContactProjection::projectEntry(std::size_t j, std::vector<int>& firstTouches, bool& madeStuck) const
{
    Particles& p = particles;
    const Real radius = settings.radius;
    const Real touchTolerance = Real(1e-6) * radius;
    const Index i = planes.mass(j);
    for (std::size_t k = planes.firstPlane(j); k < planes.endPlane(j); ++k)
    {
        if (p.pinned[i] || stuck.stuck[i])
        {
            continue; // (a plane earlier in this loop may have just made it stuck)
        }
        const ContactPlanes::Surface& plane = planes.surface(k);
        const Real nx = plane.normal.x();
        const Real ny = plane.normal.y();
        const Real nz = plane.normal.z();
        // A still surface's velocity is +0 in every bit, so the constant gives the very same arithmetic.
        const Vec3 surfaceVelocity = Still ? Vec3(Vec3::Zero()) : planes[k].velocity;
        const Real ux = surfaceVelocity.x();
        const Real uy = surfaceVelocity.y();
        const Real uz = surfaceVelocity.z();
        Real* const x = p.position[i].data();
        const Real offset = plane.offset + ((nx * ux + ny * uy) + nz * uz) * elapsed;
        const Real separation = ((nx * x[0] + ny * x[1]) + nz * x[2]) - offset - radius;
        bool arrived = false;
        if constexpr (Constrained)
        {
            if (constraints.resting(i) && constraints.restingPlane(i) == k)
            {
                // The solve kept this resting mass moving with its surface; only a position error is left to mend
                // (say, a surface that started moving within the last frame).
                if (separation < 0)
                {
                    x[0] -= separation * nx;
                    x[1] -= separation * ny;
                    x[2] -= separation * nz;
                }
                continue;
            }
            // A mass that arrived at this surface in the solve: the solve stopped its approach with an impulse,
            // which gives its friction as the approach the projection stops gives any other's.
            arrived = constraints.arrived(i) && constraints.restingPlane(i) == k;
        }
        if (separation >= touchTolerance && !arrived)
        {
            continue;
        }
        if (separation < 0)
        {
            x[0] -= separation * nx;
            x[1] -= separation * ny;
            x[2] -= separation * nz;
        }
        report.touchInChunk(i, plane.obstacle, plane.face, firstTouches);

        Real* const v = p.velocity[i].data();
        const Real rx = v[0] - ux;
        const Real ry = v[1] - uy;
        const Real rz = v[2] - uz;
        const Real normalSpeed = (rx * nx + ry * ny) + rz * nz;
        Real stopped = -normalSpeed; // the normal speed the contact takes away
        if (arrived)
        {
            stopped =
                std::max(Real(0), -normalSpeed) + std::max(Real(0), constraints.arrivalImpulse(i)) * p.inverseMass[i];
        }
        else if (normalSpeed >= 0)
        {
            continue; // already leaving the surface
        }
        Real tx = rx - normalSpeed * nx;
        Real ty = ry - normalSpeed * ny;
        Real tz = rz - normalSpeed * nz;
        const ContactResponse response = settings.responseOf(plane.obstacle);
        switch (response)
        {
        case ContactResponse::Sticky:
            tx = 0;
            ty = 0;
            tz = 0;
            break;
        case ContactResponse::Friction:
        {
            const Real budget = settings.frictionOf(plane.obstacle) * stopped;
            const Real speed = std::sqrt((tx * tx + ty * ty) + tz * tz);
            if (speed <= budget)
            {
                tx = 0;
                ty = 0;
                tz = 0;
            }
            else
            {
                const Real keep = (speed - budget) / speed;
                tx *= keep;
                ty *= keep;
                tz *= keep;
            }
            break;
        }
        case ContactResponse::Frictionless:
            break;
        }
        const Real before[3] = {v[0], v[1], v[2]};
        v[0] = ux + tx;
        v[1] = uy + ty;
        v[2] = uz + tz;
        const Real dx = v[0] - before[0];
        const Real dy = v[1] - before[1];
        const Real dz = v[2] - before[2];
        const Real m = p.mass[i];
        report.addImpulse(i, Vec3(m * dx, m * dy, m * dz));
        // The integrator already moved the mass with its velocity from before the contact. Move it by the
        // tangential change too, as if the impulse had come first; otherwise a mass held by static friction
        // would creep by h^2 g sin(a) every substep. (The normal part is handled by the projection.) BDF2 moves a
        // mass by 2h/3 of its new velocity: moved by h, a mass against an obstacle's side lost more of its slide
        // than its velocity did, and the two never agreed again (the drop scene's sheet slid on along the valley).
        const Real along = (dx * nx + dy * ny) + dz * nz;
        x[0] += moveStep * (dx - along * nx);
        x[1] += moveStep * (dy - along * ny);
        x[2] += moveStep * (dz - along * nz);
        if (response == ContactResponse::Sticky)
        {
            stuck.stick(i, p.position[i], planes[k]);
            madeStuck = true;
        }
    }
}
} // namespace masse
