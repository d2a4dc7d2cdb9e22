#pragma once
/// One sheet as the engine sees it: masses, springs, the dynamic springs of the user, and the force settings.

#include "core/forces/UserSprings.h"
#include "core/lattice/Lattice.h"
#include "core/lattice/Particles.h"
#include "core/lattice/SpringSet.h"

#include <array>

namespace masse
{
/// Forces that act on every mass.
struct ForceSettings
{
    Vec3 gravity = Vec3(0, -standardGravity, 0); ///< m/s^2
    Real airDamping = 0;                         ///< 1/s, drag f = -airDamping m v (see Damping.h)
    /// k_r (N m^2) of the compression repulsion; 0 switches it off. It acts only on springs shorter than their rest
    /// length (see SpringForce.h).
    Real repulsion = 0;
};

struct MassSpringSystem
{
    Particles particles;
    SpringSet springs;
    ForceSettings forces;
    UserSprings userSprings;
    /// Bumped by every change made between steps that a cached integrator state depends on (pins, user springs,
    /// teleported masses, new coefficients); see markChanged.
    std::uint64_t revision = 0;

    void markChanged() { ++revision; }
    std::size_t massCount() const { return particles.size(); }
    std::size_t springCount() const { return springs.size(); }
};

/// What a sheet is made of, per class of spring. Defaults are the paper's Table 1 in SI units.
struct SheetParams
{
    Real massPerMass = 0.001; ///< kg (1.0 g)
    std::array<SpringClassParams, springClassCount> springClasses = {
        SpringClassParams{9.2 * standardGravity, 0.06}, ///< planar: 9.2 g/mm = 90.2 N/m, 6% of critical damping
        SpringClassParams{6.2 * standardGravity, 0.06}, ///< inter-layer: 6.2 g/mm = 60.8 N/m
    };
};

/// Throws InputError naming the first non-positive mass, negative stiffness or damping ratio.
void validate(const SheetParams& params);

/// Builds the masses and springs of a sheet from a lattice; the system starts at rest with the paper's gravity and
/// no damping of the air (set forces.airDamping for that).
MassSpringSystem makeSheet(const Lattice& lattice, const SheetParams& params);

/// Sets every spring's k_s and k_d from its class (k_d from the class's damping ratio and the masses it joins).
void applySpringClasses(MassSpringSystem& system, const std::array<SpringClassParams, springClassCount>& classes);
} // namespace masse
