#pragma once
/// A constraint on a mass's velocity during the next step, for the implicit integrator: a mass held by sticky
/// contact moves with its surface (all three directions); a mass resting on a surface keeps the surface's normal
/// velocity, and its friction acts as a tangential damping. The implicit solve honours them with Baraff and Witkin's
/// filter. Without them it would solve resting masses as if they were falling freely: the contact would stop them
/// after the solve, while the rest of the sheet had already been moved as though they fell, and the sheet would
/// settle in a false equilibrium full of spring stress (or, with stuck masses, sag and fold a little every step).
/// For the same reason a mass about to touch gets a speculative constraint: if the step would carry it through its
/// surface, it arrives there inside the solve, and the masses joined to it are stopped with it.
/// The explicit integrators do not need them: the contact solver projects after every small substep.

#include "core/Types.h"

namespace masse
{
struct VelocityConstraint
{
    Index mass = 0;
    /// Constrained directions: 1 normal (resting contact), or 3 (held: the normal is unused).
    int directions = 1;
    Vec3 normal = Vec3::UnitY();
    Vec3 velocity = Vec3::Zero(); ///< the velocity the constrained directions must have (the surface's)
    /// N s/m, on the tangential velocity relative to the surface: Coulomb friction of a mass in resting contact,
    /// regularised (c = mu press / max(|slip|, v0)) so that it sits inside the solve as a damping.
    Real tangentialDamping = 0;
    /// Written back by the integrator after its solve: the impulse (N s) the constraint applied to the mass over the
    /// step, from the unfiltered rows, r = A dv - b. Its normal part tells a pressed contact (positive) from one the
    /// mass is leaving (negative); it is the contact force times the step.
    Vec3 reaction = Vec3::Zero();
    /// A speculative constraint, for a mass that does not touch its surface yet: the solve honours it only if the step
    /// would carry the mass through the surface, and then only while the surface has to push (see ImplicitSolve.h).
    bool speculative = false;
    /// m, speculative only: how far the mass would be in front of the surface at the step's end if it did not move.
    Real gap = 0;
    /// Written back by the integrator, speculative only: whether it honoured the constraint in its final solve.
    bool engaged = false;
    /// Written back by the integrator: it was honoured, then released because its reaction pulled (a speculative one
    /// that was engaged, or, under BDF2, a resting one whose mass leaves its surface within the step).
    bool released = false;

    /// Coulomb's coefficient of the friction that tangentialDamping stands for (0: none given). With it a solve may
    /// lower tangentialDamping so that the friction impulse stays within mu times the constraint's normal reaction.
    Real friction = 0;

    /// Whether the solve honours it now: always, unless it is speculative and not engaged.
    bool honoured() const { return !released && (!speculative || engaged); }
};
} // namespace masse
