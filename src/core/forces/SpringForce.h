#pragma once
/// The force of one sheet spring (paper section 2), as a stateless kernel shared by the force loop, the implicit
/// solver and the tests.
///
/// With d = x_a - x_b and its unit vector n = d / |d|, the force on a is
///     f_a = -( k_s (|d| - s) + k_d (v_a - v_b) . n ) n            (Hooke plus damping along the spring)
///         + k_r (1/|d|^2 - 1/s^2) n       when |d| < s             (compression repulsion)
/// and f_b = -f_a. The paper prints the repulsion as f = -k_r d/|d|^3; with d = p - q that would pull p toward q, so
/// we use the sign that pushes the masses apart, and subtract its value at the rest length so the force is continuous
/// at |d| = s (a jump there would add energy each time a spring crosses its rest length).

#include "core/Types.h"

namespace masse
{
/// Hooke and damping part of the force on a along n (positive pushes a away from b).
inline Real hookeMagnitude(Real length, Real closingSpeed, Real stiffness, Real damping, Real restLength)
{
    return -(stiffness * (length - restLength) + damping * closingSpeed);
}

/// Compression repulsion on a along n: positive (pushing apart) below the rest length, zero above it.
inline Real repulsionMagnitude(Real length, Real restLength, Real repulsion)
{
    if (length >= restLength)
    {
        return 0;
    }
    return repulsion * (Real(1) / (length * length) - Real(1) / (restLength * restLength));
}

/// Signed magnitude of the whole spring force on a along n (positive pushes a away from b).
inline Real springForceMagnitude(Real length, Real closingSpeed, Real stiffness, Real damping, Real restLength,
                                 Real repulsion)
{
    return hookeMagnitude(length, closingSpeed, stiffness, damping, restLength) +
           repulsionMagnitude(length, restLength, repulsion);
}

/// Potential energy of the spring and its repulsion at length `length`.
inline Real springPotential(Real length, Real stiffness, Real restLength, Real repulsion)
{
    const Real stretch = length - restLength;
    Real energy = Real(0.5) * stiffness * stretch * stretch;
    if (length < restLength)
    {
        // Integral of the repulsion from length to restLength.
        energy += repulsion * (Real(1) / length + length / (restLength * restLength) - Real(2) / restLength);
    }
    return energy;
}

/// Below this fraction of its rest length a spring's direction is taken as undefined and the spring exerts nothing,
/// rather than dividing by a vanishing length.
inline constexpr Real degenerateLengthFraction = 1e-9;
} // namespace masse
