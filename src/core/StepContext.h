#pragma once
/// What a frame's stages hand one another besides the sheet's state, passed to the stages that read or write it
/// instead of riding on MassSpringSystem: the contact solver writes the implicit integrators' velocity constraints at
/// the frame's start, each implicit solve writes their reactions back, and the contact solver reads them after the
/// substep. The Simulator owns one and passes it through the frame.

#include "VelocityConstraint.h"

#include <vector>

namespace masse
{
struct StepContext
{
    /// Velocity constraints for this frame's substeps (empty: none), honoured by the integrators whose
    /// honoursConstraints() is true; each solve writes every constraint's reaction.
    std::vector<VelocityConstraint> constraints;
};
} // namespace masse
