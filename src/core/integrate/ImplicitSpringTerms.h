#pragma once
/// Each spring's part of the implicit step's linear system, computed once per assembly and gathered by both its masses
/// (ImplicitSolve::assemble): its 3x3 block and its right-hand side term.

#include "core/MassSpringSystem.h"
#include "core/Types.h"
#include "core/forces/SimdPath.h"

#include <array>
#include <cstdint>
#include <vector>

namespace masse
{
/// One spring's term. The block is exactly symmetric (n_r n_c and n_c n_r are the same product), so its upper triangle
/// holds it.
struct SpringTerm
{
    std::array<Real, 6> upper; ///< of a k_d n n^T - a^2 K_aa, by rows: xx xy xz yy yz zz
    Vec3 kv;                   ///< a K_aa (a v_ab + d_ab): taken from a's right-hand side, given to b's

    Mat3 block() const
    {
        Mat3 b;
        b << upper[0], upper[1], upper[2], upper[1], upper[3], upper[4], upper[2], upper[4], upper[5];
        return b;
    }
};

/// What the terms of a step depend on besides the sheet.
struct SpringTermInputs
{
    Real a = 0;                                ///< s, the step's a (h for backward Euler)
    const std::vector<Vec3>* offset = nullptr; ///< m, per mass, added to a v in the move; null or empty for none
};

/// The terms of springs [begin, end) at the sheet's positions and velocities. `engaged[s]` is false for a spring too
/// short to have a direction, which adds nothing (its term is then left unspecified). Blocks of a gathering loop
/// (end positions and velocities by index) and a computing loop without indirection, which vectorises; element-wise
/// IEEE arithmetic, so the same bits on every SIMD path (SimdPath.h).
void computeSpringTerms(SimdPath path, const MassSpringSystem& system, const SpringTermInputs& inputs,
                        std::size_t begin, std::size_t end, SpringTerm* terms, std::uint8_t* engaged);
} // namespace masse
