#pragma once
/// The yardstick of `masse bench --baseline`: a plain single-threaded scalar loop over a sheet's springs, as one would
/// first write it (scatter f to both ends, then a symplectic Euler update), timed in the same process as the engine.

#include "core/MassSpringSystem.h"

#include <cstdint>

namespace masse::app
{
/// Advances a copy of `system` by `substeps` substeps of h with the plain loop (gravity, air drag, Hooke and damping;
/// no repulsion, no user springs) and returns the wall-clock seconds it took.
double timeScalarBaseline(const MassSpringSystem& system, Real h, std::uint64_t substeps);
} // namespace masse::app
