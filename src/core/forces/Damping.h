#pragma once
/// How the paper's two damping figures (Table 1) become forces.
///
/// Air damping "0.97 (3%)": a mass keeps 97% of its velocity over one of the paper's 0.03 s steps. We turn that into
/// a linear drag f = -c m v with the rate c = -ln(0.97) / 0.03 s = 1.015 1/s, so the decay is the same whatever step
/// or integrator is used (the paper multiplied velocities by 0.97 each step, which ties the damping to dt).
///
/// Sheet damping "6.0%": each spring's dashpot k_d gives the two masses it joins 6% of critical damping,
/// k_d = 2 * 0.06 * sqrt(k_s mu) with mu = m_a m_b / (m_a + m_b), the two-body reduced mass. A ratio is what stays
/// meaningful when the lattice is refined and masses and stiffnesses change.

#include "core/Types.h"

#include <cmath>

namespace masse
{
/// The paper's time step, the interval its air-damping factor refers to.
inline constexpr Real paperTimeStep = 0.03;
inline constexpr Real paperAirRetention = 0.97;
inline constexpr Real paperSheetDampingRatio = 0.06;

/// Drag rate c (1/s) for a mass that keeps `retainedFraction` of its velocity over `interval` seconds.
inline Real airDampingRate(Real retainedFraction, Real interval)
{
    return -std::log(retainedFraction) / interval;
}

/// Dashpot constant k_d (N s/m) giving a spring of stiffness k between masses ma and mb the damping ratio `ratio`.
inline Real springDampingCoefficient(Real stiffness, Real ratio, Real massA, Real massB)
{
    const Real reducedMass = massA * massB / (massA + massB);
    return Real(2) * ratio * std::sqrt(stiffness * reducedMass);
}
} // namespace masse
