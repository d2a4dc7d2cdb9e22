#include "core/MassSpringSystem.h"

#include "core/Format.h"
#include "core/InputError.h"
#include "core/forces/Damping.h"

#include <cmath>
#include <string>

namespace masse
{
void validate(const SheetParams& params)
{
    if (!(params.massPerMass > 0) || !std::isfinite(params.massPerMass))
    {
        throw InputError("massPerMass",
                         "must be a positive number of kg (got " + formatNumber(params.massPerMass) + ")");
    }
    for (int cls = 0; cls < springClassCount; ++cls)
    {
        const SpringClassParams& p = params.springClasses[std::size_t(cls)];
        const std::string field = "springClasses[" + std::to_string(cls) + "]";
        if (!(p.stiffness > 0) || !std::isfinite(p.stiffness))
        {
            throw InputError(field + ".stiffness",
                             "must be a positive number of N/m (got " + formatNumber(p.stiffness) + ")");
        }
        if (!(p.dampingRatio >= 0) || !std::isfinite(p.dampingRatio))
        {
            throw InputError(field + ".dampingRatio", "must be >= 0 (got " + formatNumber(p.dampingRatio) + ")");
        }
    }
}

MassSpringSystem makeSheet(const Lattice& lattice, const SheetParams& params)
{
    validate(params);
    MassSpringSystem system;
    for (const Vec3& x : lattice.position)
    {
        system.particles.add(x, params.massPerMass);
    }
    system.springs = lattice.springs;
    applySpringClasses(system, params.springClasses);
    return system;
}

void applySpringClasses(MassSpringSystem& system, const std::array<SpringClassParams, springClassCount>& classes)
{
    SpringSet& springs = system.springs;
    const std::vector<Real>& mass = system.particles.mass;
    std::vector<Real>& stiffness = springs.mutableStiffness();
    std::vector<Real>& damping = springs.mutableDamping();
    for (std::size_t s = 0; s < springs.size(); ++s)
    {
        const SpringClassParams& p = classes[std::size_t(springs.classes()[s])];
        const SpringEnds e = springs.ends()[s];
        stiffness[s] = p.stiffness;
        damping[s] = springDampingCoefficient(p.stiffness, p.dampingRatio, mass[e.a], mass[e.b]);
    }
    // Equal masses give every spring of a class the same k_d: the force kernel then reads each class's pair.
    springs.summariseUniformClasses();
    system.markChanged();
}
} // namespace masse
