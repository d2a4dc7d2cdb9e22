#pragma once
/// The dynamic spring the mouse pulls a picked mass with (paper section 7: a spring from the nearest mass to the
/// cursor, rather than moving the mass, so the simulation stays stable). Capped as Box2D caps its mouse joint.

#include "core/MassSpringSystem.h"
#include "core/integrate/Integrator.h"

namespace masse::viewer
{
/// How the pick spring is sized from the sheet it acts on.
struct PickSpringTuning
{
    /// The spring's frequency on the picked mass, as a fraction of the sheet's stiffest mode. Below 1 it never becomes
    /// the stiffest spring: the explicit integrators' substep (set by that mode) barely changes, and the implicit one
    /// meets no mode stiffer than the sheet's own.
    Real frequencyFraction = Real(0.25);
    /// Fraction of critical damping of the spring on the picked mass (Box2D's mouse joint default).
    Real dampingRatio = Real(0.7);
    /// The pull's cap, in weights of the whole sheet: enough to lift it, no more (Box2D caps at a multiple of the
    /// body's weight too).
    Real maxForceInSheetWeights = Real(2);
};

/// A spring from `mass` to `target`, sized for this sheet: stiffness m (f w)^2 with w the sheet's highest frequency
/// (Gershgorin bound, as the Simulator's substepping uses), damping from `dampingRatio`, and the pull capped at
/// `maxForceInSheetWeights` times the sheet's weight (under standard gravity if the scene's is weaker).
UserSpring makePickSpring(const MassSpringSystem& system, Index mass, const Vec3& target,
                          const PickSpringTuning& tuning = {});
} // namespace masse::viewer
