#pragma once
/// Energies of a sheet, for conservation tests, rest detection and reports.

#include "core/MassSpringSystem.h"

namespace masse
{
struct Energy
{
    Real kinetic = 0;     ///< J
    Real gravity = 0;     ///< J, -m g . x (zero at the origin)
    Real springs = 0;     ///< J, sheet springs and their repulsion
    Real userSprings = 0; ///< J, uncapped part only
    Real total() const { return kinetic + gravity + springs + userSprings; }
};

/// Kinetic energy of the free masses (pinned masses have none).
Real kineticEnergy(const Particles& particles);
Energy computeEnergy(const MassSpringSystem& system);
} // namespace masse
