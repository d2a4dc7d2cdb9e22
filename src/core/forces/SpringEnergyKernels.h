#pragma once
/// The divergence guard's spring passes over a range of springs: the springs' energy, and after an implicit substep the
/// linearisation gap with it. Each runs in blocks of two loops, as the force kernel does (Forces.cpp): one gathers
/// each spring's end positions by index, the other computes without indirection, so that its square roots and
/// divisions go several at a time; then each block's per-spring figures are added in spring order. Element-wise IEEE
/// arithmetic and an order fixed by the spring index: the same bits on every SIMD path (SimdPath.h) and, over fixed
/// chunks, at any thread count.

#include "core/MassSpringSystem.h"
#include "core/Types.h"
#include "core/forces/SimdPath.h"

#include <vector>

namespace masse
{
/// The springs [begin, end)'s energy at the system's positions (J), summed in spring order.
Real springEnergyOfRange(SimdPath path, const MassSpringSystem& system, std::size_t begin, std::size_t end);

/// Both figures of springs [begin, end) after an implicit substep that started at `start`: their energy now, as
/// springEnergyOfRange gives it, and the linearisation gap (see DivergenceGuard::afterIntegrator), each summed in
/// spring order.
struct SpringEnergyAndGap
{
    Real energy = 0; ///< J
    Real gap = 0;    ///< J
};
SpringEnergyAndGap springEnergyAndGapOfRange(SimdPath path, const MassSpringSystem& system,
                                             const std::vector<Vec3>& start, std::size_t begin, std::size_t end);
} // namespace masse
