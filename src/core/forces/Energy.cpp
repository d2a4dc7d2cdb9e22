#include "core/forces/Energy.h"

#include "core/forces/SpringForce.h"

namespace masse
{
Real kineticEnergy(const Particles& p)
{
    Real kinetic = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
    {
        kinetic += Real(0.5) * p.mass[i] * p.velocity[i].squaredNorm();
    }
    return kinetic;
}

Energy computeEnergy(const MassSpringSystem& system)
{
    const Particles& p = system.particles;
    Energy e;
    e.kinetic = kineticEnergy(p);
    for (std::size_t i = 0; i < p.size(); ++i)
    {
        if (!p.pinned[i])
        {
            e.gravity -= p.mass[i] * system.forces.gravity.dot(p.position[i]);
        }
    }
    const SpringSet& s = system.springs;
    for (std::size_t k = 0; k < s.size(); ++k)
    {
        const Real length = (p.position[s.ends()[k].a] - p.position[s.ends()[k].b]).norm();
        e.springs += springPotential(length, s.stiffness()[k], s.restLength()[k], system.forces.repulsion);
    }
    for (const UserSpring& spring : system.userSprings.all())
    {
        e.userSprings += Real(0.5) * spring.stiffness * (p.position[spring.mass] - spring.target).squaredNorm();
    }
    return e;
}
} // namespace masse
