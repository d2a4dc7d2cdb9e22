#pragma once
/// What a frame's stages hand one another besides the sheet's state, passed to the stages that read or write it
/// instead of riding on MassSpringSystem or on pointers from one model into another. The Simulator owns one and passes
/// it through the frame's stages (StepStage.h): to the integrator and every StepHook. How the Simulator takes the frame
/// (its substeps, one solve or several) is not here but in FramePlan.
///
/// Who writes what:
/// - the contact solver writes the implicit integrators' velocity constraints at the frame's start, each implicit
///   solve writes their reactions back, and the contact solver reads them after the substep;
/// - the obstacle contact publishes its report's per-mass obstacles after each of its stages;
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
    /// s: how far a change of a mass's velocity after the substep just taken moves the mass, as the integrator placed
    /// it (x' = ... + moveStep v'). The Simulator sets the substep before each integrator step; BDF2 sets its 2h/3.
    /// The contact's projection moves a mass whose velocity its friction changed by this times the change.
    Real moveStep = 0;
};
} // namespace masse
