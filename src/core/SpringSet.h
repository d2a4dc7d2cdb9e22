#pragma once
/// The springs of a sheet: topology (which masses, rest length, class) apart from coefficients.
///
/// Topology (the ends) is append-only: springs are added while a lattice is built and never rewired, so the adjacency
/// the force kernels gather through is built once, on first use, and shared by copies. Coefficients start from the
/// spring's class (planar or inter-layer) and may later be rewritten per spring (heat changes stiffness), so the force
/// kernel reads them per spring.

#include "SpringAdjacency.h"
#include "SpringRowPlan.h"
#include "Types.h"

#include <array>
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

    /// The springs at each of `massCount` masses; built on the first call (and again if springs were added since),
    /// from one thread, before kernels run in parallel.
    const SpringAdjacency& adjacency(std::size_t massCount) const
    {
        if (!m_adjacency || m_adjacency->springCount != ends.size() || m_adjacency->massCount() != massCount)
        {
            m_adjacency = std::make_shared<const SpringAdjacency>(buildSpringAdjacency(ends, massCount));
        }
        return *m_adjacency;
    }

    void add(Index a, Index b, Real rest, SpringClass cls)
    {
        ends.push_back({a, b});
        restLength.push_back(rest);
        springClass.push_back(cls);
        stiffness.push_back(0);
        damping.push_back(0);
    }

    /// The springs and masses by lattice row, for the banded force kernel; set by the lattice builders, shared by
    /// copies, and used only while it still matches the set (see SpringRowPlan.h).
    std::shared_ptr<const SpringRowPlan> rowPlan;

private:
    mutable std::shared_ptr<const SpringAdjacency> m_adjacency;
};
} // namespace masse
