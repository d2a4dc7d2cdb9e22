#pragma once
/// What a frame's stages hand one another besides the sheet's state, passed to the stages that read or write it
/// instead of riding on MassSpringSystem or on pointers from one model into another. The Simulator owns one and passes
/// it through the frame: to the contact solver, the integrator and every StepHook.
///
/// Who writes what:
/// - the contact solver writes the implicit integrators' velocity constraints at the frame's start, each implicit
///   solve writes their reactions back, and the contact solver reads them after the substep;
/// - the Simulator publishes the contact report's per-mass obstacles after each contact stage;
/// - the heat model publishes its temperatures and the sheet's thickness at the start of each frame (or the program
///   that owns a SheetThickness without a heat model sets `thickness` once), before the hooks added after it read
///   them.

#include "core/Types.h"
#include "core/integrate/VelocityConstraint.h"

#include <span>
#include <vector>

namespace masse
{
class SheetThickness;

struct StepContext
{
    /// Velocity constraints for this frame's substeps (empty: none), honoured by the integrators whose
    /// honoursConstraints() is true; each solve writes every constraint's reaction.
    std::vector<VelocityConstraint> constraints;
    /// Per mass, the obstacle it touches (its index) or -1, as of the contact solver's last stage; empty without a
    /// contact solver. Read by the heat model's contact exchange and the pressure load's seal.
    std::span<const int> touchingObstacle;
    /// Per mass, temperature (K); empty without a heat model. Read by the temperature-dependent springs.
    std::span<const Real> temperature;
    /// The sheet's local thickness, updated from the positions by the springs that follow it; null: none.
    SheetThickness* thickness = nullptr;
    /// False when every external force is +0 (noExternalForces in Forces.h): the symplectic pass then need not read
    /// them. The Simulator looks once a frame, after the hooks that start it, and again after every substep's hooks
    /// when a hook says it writes them then (StepHook::writesExternalForcesMidFrame; a pressure load does); nothing
    /// else in a step writes them.
    bool externalForces = true;
    /// Whether somebody reads particles.force after this substep: the Simulator sets it for a frame's last substep
    /// (the contact's reach and the guard read them between frames), for every substep while a contact holds a
    /// stuck mass (its release force), and when a hook says it reads them (StepHook::readsForcesMidFrame). When it is
    /// false the symplectic pass need not store them.
    bool forcesRead = true;
    /// Whether the integrator takes each frame in one solve (the implicit ones), set by the Simulator at each frame's
    /// start: a stage that relies on short substeps to catch up (the self-contact) then has none after the solve.
    bool oneSolveAFrame = false;
    /// s: how far a change of a mass's velocity after the substep just taken moves the mass, as the integrator placed
    /// it (x' = ... + moveStep v'). The Simulator sets the substep before each integrator step; BDF2 sets its 2h/3.
    /// The contact's projection moves a mass whose velocity its friction changed by this times the change.
    Real moveStep = 0;
};
} // namespace masse
