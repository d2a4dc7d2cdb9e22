#include "core/material/MembraneStiffness.h"

#include "core/Format.h"
#include "core/InputError.h"

#include <cmath>
#include <string>

namespace masse
{
std::vector<Real> stiffnessPerModulus(const Lattice& lattice, Real thickness, Real interLayerRatio)
{
    if (!(thickness > 0) || !std::isfinite(thickness))
    {
        throw InputError("thickness", "must be a positive number of m (got " + formatNumber(thickness) + ")");
    }
    if (!(interLayerRatio > 0) || !std::isfinite(interLayerRatio))
    {
        throw InputError("interLayerRatio", "must be a positive number (got " + formatNumber(interLayerRatio) + ")");
    }
    const Real layerThickness = thickness / Real(lattice.spec.layers);
    const Real shape = lattice.spec.structure == Structure::TRiMM ? std::sqrt(Real(3)) / Real(2) : Real(1);
    const Real planar = shape * layerThickness;
    std::vector<Real> perModulus(lattice.springCount());
    for (std::size_t s = 0; s < perModulus.size(); ++s)
    {
        perModulus[s] = lattice.springs.classes()[s] == SpringClass::Planar ? planar : interLayerRatio * planar;
    }
    return perModulus;
}
} // namespace masse
