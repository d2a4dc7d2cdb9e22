#pragma once
/// The spring-force kernel of lattice sheets: it streams through a SpringRowPlan's bands of rows, vectorised across
/// neighbouring springs and masses, on every thread. Forces.h chooses it whenever a sheet has a plan; its results
/// have the bits of the plain per-mass gather over SpringAdjacency (see SpringRowPlan.h for why).

#include "core/Types.h"
#include "core/forces/SpringRowPlan.h"
#include "core/lattice/SpringSet.h"

namespace masse
{
/// What the banded kernel computes for every mass.
enum class BandedPass
{
    AddSpringForces,   ///< force += the sheet springs' forces
    TotalForces,       ///< force = m (g - drag v) + external + the springs' forces
    SymplecticSubstep, ///< TotalForces, then v += (h / m) force and x += h v, in place
    /// SymplecticSubstep when no mass has an external force: each is taken as +0 without reading the array, the same
    /// bits (x + 0.0 is what adding an external force of +0 computes) and a fifth less memory for the pass to stream.
    SymplecticSubstepWithoutExternalForces,
};

/// The inputs and outputs of one pass. x and v are the state the forces are evaluated at; for SymplecticSubstep they
/// must be `position` and `velocity`, which the pass then moves.
struct BandedForceArgs
{
    const SpringRowPlan* plan = nullptr;
    const SpringSet* springs = nullptr;
    Real repulsion = 0;
    const Vec3* x = nullptr;
    const Vec3* v = nullptr;
    /// Where the forces go. A symplectic pass may be given null when nobody reads this substep's forces: it then
    /// stores none (the other passes need it).
    Vec3* force = nullptr;
    // TotalForces and SymplecticSubstep
    const Real* mass = nullptr;
    const Vec3* externalForce = nullptr;
    Vec3 gravity = Vec3::Zero();
    Real drag = 0;
    // SymplecticSubstep
    Real h = 0;
    const Real* inverseMass = nullptr;
    Vec3* position = nullptr;
    Vec3* velocity = nullptr;
};

/// Runs one pass over the whole sheet: the spring rows between bands first, then every band, in parallel.
void runBandedForces(BandedPass pass, const BandedForceArgs& args);
} // namespace masse
