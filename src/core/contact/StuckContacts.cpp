#include "core/contact/StuckContacts.h"

namespace masse
{
void StuckContacts::followSurfaces(ContactDetector& detector, Real dt)
{
    if (!any)
    {
        return;
    }
    for (std::size_t i = 0; i < stuck.size(); ++i)
    {
        if (stuck[i])
        {
            velocity[i] = detector.pointVelocity(obstacle[i], anchor[i], dt);
        }
    }
}

void StuckContacts::hold(Particles& p, Real h, Real releaseForce, ContactReport& report, Real time)
{
    if (!any)
    {
        return;
    }
    for (std::size_t i = 0; i < p.size(); ++i)
    {
        if (!stuck[i])
        {
            continue;
        }
        const Real pull = p.force[i].dot(normal[i]);
        if (releaseForce > 0 && pull > releaseForce)
        {
            stuck[i] = 0;
            continue;
        }
        anchor[i] += h * velocity[i];
        report.addImpulse(i, p.mass[i] * (velocity[i] - p.velocity[i]));
        p.position[i] = anchor[i];
        p.velocity[i] = velocity[i];
        report.touch(Index(i), obstacle[i], face[i], time);
    }
}
} // namespace masse
