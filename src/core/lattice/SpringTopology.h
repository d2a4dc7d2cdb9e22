#pragma once
/// Which masses each spring of a sheet joins and why: the part of a sheet's springs that never changes once built.
///
/// A lattice builder (or a test) builds it once; every copy of the sheet then shares it read-only, as do the models
/// that read the sheet's structure (the heat model, the viscoelastic springs, thickness, the renderer), so copying a
/// sheet copies a pointer, not its springs. What changes from step to step (rest lengths, stiffness, damping) is the
/// SpringSet's own.

#include "core/Types.h"
#include "core/forces/SpringRowPlan.h"

#include <memory>
#include <vector>

namespace masse
{
/// Why a spring exists; each class has its own stiffness and damping (paper Table 1: planar 9.2 g/mm,
/// inter-layer 6.2 g/mm).
enum class SpringClass : std::uint8_t
{
    Planar = 0,     ///< joins two masses of one layer (grid edges and SLaMM braces)
    InterLayer = 1, ///< joins a mass to the masses of the layer below it
};
inline constexpr int springClassCount = 2;

struct SpringEnds
{
    Index a;
    Index b;
};

struct SpringTopology
{
    std::vector<SpringEnds> ends;
    std::vector<SpringClass> springClass;
    std::vector<Real> restLength; ///< m, as built (the lattice's own spacings)
    /// The springs and masses by lattice row, for the banded force kernel: set by buildLattice, which knows each
    /// mass's row; null for a spring set built otherwise (the kernel then gathers through SpringAdjacency).
    std::shared_ptr<const SpringRowPlan> rowPlan;

    std::size_t size() const { return ends.size(); }
};
} // namespace masse
