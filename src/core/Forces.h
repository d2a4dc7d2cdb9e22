#pragma once
/// Total force on every mass: gravity, external forces, air drag, sheet springs (with damping and repulsion) and
/// user springs.

#include "MassSpringSystem.h"

namespace masse
{
/// Writes into `force` the total force at positions `x` and velocities `v` (which need not be the system's own:
/// integrators evaluate at predicted states). `force` is resized to the mass count.
void evaluateForces(const MassSpringSystem& system, const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                    std::vector<Vec3>& force);

/// The first half of a symplectic Euler substep in one pass over the masses: evaluates the forces at the system's own
/// state into particles.force and updates each velocity by (h / m) f as soon as its force is summed (the same
/// arithmetic as a separate loop, so the same bits, with one pass less over memory). Returns false, doing nothing,
/// when the system has user springs (their forces are added after the gather): use evaluateForces then.
bool evaluateForcesAndKick(MassSpringSystem& system, Real h);

/// Adds the sheet springs' forces only (the hot loop; exposed for benchmarks).
void accumulateSpringForces(const SpringSet& springs, Real repulsion, const std::vector<Vec3>& x,
                            const std::vector<Vec3>& v, std::vector<Vec3>& force);
} // namespace masse
