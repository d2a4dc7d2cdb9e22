#pragma once
/// The springs of a sheet: topology (which masses, rest length, class) apart from coefficients.
///
/// Topology is fixed once a lattice is built. Coefficients start from the spring's class (planar or inter-layer) and
/// may later be rewritten per spring (heat changes stiffness), so the force kernel reads them per spring.

#include "Types.h"

#include <array>
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

/// Stiffness and damping of one class of springs.
struct SpringClassParams
{
    Real stiffness = 0;    ///< N/m
    Real dampingRatio = 0; ///< fraction of critical damping of the two-mass spring, e.g. 0.06 for Table 1's 6%
};

struct SpringSet
{
    // Topology
    std::vector<SpringEnds> ends;
    std::vector<Real> restLength; ///< m
    std::vector<SpringClass> springClass;

    // Coefficients, one per spring
    std::vector<Real> stiffness; ///< k_s, N/m
    std::vector<Real> damping;   ///< k_d, N s/m

    std::size_t size() const { return ends.size(); }

    void add(Index a, Index b, Real rest, SpringClass cls)
    {
        ends.push_back({a, b});
        restLength.push_back(rest);
        springClass.push_back(cls);
        stiffness.push_back(0);
        damping.push_back(0);
    }
};
} // namespace masse
