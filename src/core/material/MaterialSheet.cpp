#include "core/material/MaterialSheet.h"

#include "core/Format.h"
#include "core/InputError.h"
#include "core/forces/Damping.h"
#include "core/material/Thickness.h"

#include <cmath>
#include <string>

namespace masse
{
MassSpringSystem makeMaterialSheet(const Lattice& lattice, const Material& material, Real thickness, Real temperature,
                                   Real dampingRatio, Real interLayerRatio)
{
    validate(material);
    if (!(temperature > 0) || !std::isfinite(temperature))
    {
        throw InputError("temperature", "must be above absolute zero (got " + formatNumber(temperature) + " K)");
    }
    if (!(dampingRatio >= 0 && dampingRatio <= 1))
    {
        throw InputError("dampingRatio", "must be in [0, 1] (got " + formatNumber(dampingRatio) + ")");
    }
    const SheetThickness geometry(lattice, thickness);
    const std::vector<Real> perModulus = stiffnessPerModulus(lattice, thickness, interLayerRatio);

    MassSpringSystem system;
    const Real perArea = material.density * thickness / Real(lattice.spec.layers);
    for (std::size_t i = 0; i < lattice.massCount(); ++i)
    {
        system.particles.add(lattice.position[i], perArea * geometry.restArea()[i]);
    }
    system.springs = lattice.springs;
    const Real modulus = modulusAt(material, temperature);
    std::vector<Real>& stiffness = system.springs.mutableStiffness();
    std::vector<Real>& damping = system.springs.mutableDamping();
    for (std::size_t s = 0; s < system.springs.size(); ++s)
    {
        const SpringEnds e = system.springs.ends()[s];
        const Real k = perModulus[s] * modulus;
        stiffness[s] = k;
        damping[s] = springDampingCoefficient(k, dampingRatio, system.particles.mass[e.a], system.particles.mass[e.b]);
    }
    system.markChanged();
    return system;
}
} // namespace masse
