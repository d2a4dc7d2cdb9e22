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

/// Adds the sheet springs' forces only (the hot loop; exposed for benchmarks).
void accumulateSpringForces(const SpringSet& springs, Real repulsion, const std::vector<Vec3>& x,
                            const std::vector<Vec3>& v, std::vector<Vec3>& force);
} // namespace masse
