#pragma once
/// Total force on every mass: gravity, external forces, air drag, sheet springs (with damping and repulsion) and
/// user springs.

#include "core/MassSpringSystem.h"

namespace masse
{
/// Writes into `force` the total force at positions `x` and velocities `v` (which need not be the system's own:
/// integrators evaluate at predicted states). `force` is resized to the mass count.
void evaluateForces(const MassSpringSystem& system, const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                    std::vector<Vec3>& force);

/// One symplectic Euler substep of the system's own state: evaluates the forces into particles.force, then
/// v += (h / m) f and x += h v. A lattice sheet (a SpringRowPlan) does all three in one pass over its bands of rows;
/// other spring sets in a gather pass and a drift pass. The same bits either way as evaluateForces followed by the two
/// updates. Returns false, doing nothing, when the system has user springs (their forces are added after the gather):
/// use evaluateForces then. With `externalForces` false the caller vouches that every external force is +0 in every
/// bit (noExternalForces), and a lattice sheet's pass does not read them: the same bits, less memory to stream. With
/// `storeForces` false nobody will read this substep's forces, and a lattice sheet's pass leaves particles.force as it
/// was (it then streams a sixth less memory).
bool symplecticSubstep(MassSpringSystem& system, Real h, bool externalForces = true, bool storeForces = true);

/// Whether every component of every external force is +0 in every bit (a -0 would not add as +0 does).
bool noExternalForces(const Particles& particles);

/// Adds the sheet springs' forces only (the hot loop; exposed for benchmarks).
void accumulateSpringForces(const SpringSet& springs, Real repulsion, const std::vector<Vec3>& x,
                            const std::vector<Vec3>& v, std::vector<Vec3>& force);
} // namespace masse
