#include "ContactProjection.h"

#include <algorithm>

namespace masse
{
void ContactProjection::run(std::size_t begin, std::size_t end, std::vector<int>& firstTouches, bool& madeStuck) const
{
    for (std::size_t i = begin; i < end; ++i)
    {
        if (planes.first(i) != planes.last(i))
        {
            projectMass(Index(i), firstTouches, madeStuck);
        }
    }
}

void ContactProjection::projectMass(Index i, std::vector<int>& firstTouches, bool& madeStuck) const
{
    Particles& p = particles;
    const Real radius = settings.radius;
    const Real touchTolerance = Real(1e-6) * radius;
    for (std::size_t k = planes.first(i); k < planes.last(i); ++k)
    {
        const ContactPlane& plane = planes[k];
        if (p.pinned[i] || stuck.stuck[i])
        {
            continue; // (a plane earlier in this loop may have just made it stuck)
        }
        const Real offset = plane.offset + plane.normal.dot(plane.velocity) * elapsed;
        const Real separation = plane.normal.dot(p.position[i]) - offset - radius;
        if (constraints.resting(i) && constraints.restingPlane(i) == k)
        {
            // The solve kept this resting mass moving with its surface; only a position error is left to mend
            // (say, a surface that started moving within the last frame).
            if (separation < 0)
            {
                p.position[i] -= separation * plane.normal;
            }
            continue;
        }
        // A mass that arrived at this surface in the solve: the solve stopped its approach with an impulse, which
        // gives its friction as the approach the projection stops gives any other's.
        const bool arrived = constraints.arrived(i) && constraints.restingPlane(i) == k;
        if (separation >= touchTolerance && !arrived)
        {
            continue;
        }
        if (separation < 0)
        {
            p.position[i] -= separation * plane.normal;
        }
        report.touchInChunk(i, plane.obstacle, plane.face, firstTouches);

        const Vec3 relative = p.velocity[i] - plane.velocity;
        const Real normalSpeed = relative.dot(plane.normal);
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
        const Vec3 before = p.velocity[i];
        Vec3 tangential = relative - normalSpeed * plane.normal;
        const ContactResponse response = settings.responseOf(plane.obstacle);
        switch (response)
        {
        case ContactResponse::Sticky:
            tangential.setZero();
            break;
        case ContactResponse::Friction:
        {
            const Real budget = settings.frictionOf(plane.obstacle) * stopped;
            const Real speed = tangential.norm();
            tangential = speed <= budget ? Vec3::Zero() : Vec3(tangential * ((speed - budget) / speed));
            break;
        }
        case ContactResponse::Frictionless:
            break;
        }
        p.velocity[i] = plane.velocity + tangential;
        const Vec3 change = p.velocity[i] - before;
        report.addImpulse(i, p.mass[i] * change);
        // The integrator already moved the mass with its velocity from before the contact. Move it by the
        // tangential change too, as if the impulse had come first; otherwise a mass held by static friction
        // would creep by h^2 g sin(a) every substep. (The normal part is handled by the projection.)
        p.position[i] += h * (change - change.dot(plane.normal) * plane.normal);
        if (response == ContactResponse::Sticky)
        {
            stuck.stick(i, p.position[i], plane);
            madeStuck = true;
        }
    }
}
} // namespace masse
