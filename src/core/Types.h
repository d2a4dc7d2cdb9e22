#pragma once
/// Scalar and vector types of the MaSSE core.
///
/// Everything is double precision: contact tolerances are 1% of a lattice spacing (tens of micrometres on fine
/// sheets) and the implicit solver's conjugate gradient needs the headroom. Eigen's 3-vectors of double are 24 bytes
/// and not alignment-sensitive, so they sit safely in std::vector.

#include <Eigen/Core>
#include <Eigen/Geometry> // cross products, quaternions

#include <cstdint>

namespace masse
{
using Real = double;
using Vec3 = Eigen::Matrix<Real, 3, 1>;
using Mat3 = Eigen::Matrix<Real, 3, 3>;
/// Index of a mass in a sheet. 32 bits keep spring arrays small; 4 billion masses is far beyond real time.
using Index = std::uint32_t;

/// Standard gravity (m/s^2); also converts the paper's grams-force per millimetre to N/m.
inline constexpr Real standardGravity = 9.80665;
} // namespace masse
