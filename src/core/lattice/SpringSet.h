#pragma once
/// The springs of a sheet: a shared, immutable topology (SpringTopology.h) and each spring's per-step state, its
/// current rest length, stiffness k_s and damping k_d, which a material model may rewrite every substep.
///
/// The per-step values are read through const accessors and rewritten only through the mutable ones, so the set
/// knows when every spring of a class still has its class's k_s and k_d (a sheet without a material): the banded force
/// kernel then reads two numbers per class instead of two arrays, a third of the memory it streams per substep.

#include "core/Types.h"
#include "core/lattice/SpringAdjacency.h"
#include "core/lattice/SpringTopology.h"

#include <array>
#include <memory>
#include <optional>
#include <vector>

namespace masse
{
/// Stiffness and damping of one class of springs.
struct SpringClassParams
{
    Real stiffness = 0;    ///< N/m
    Real dampingRatio = 0; ///< fraction of critical damping of the two-mass spring, e.g. 0.06 for Table 1's 6%
};

/// k_s and k_d shared by every spring of each class.
struct UniformClassCoefficients
{
    std::array<Real, springClassCount> stiffness{}; ///< N/m
    std::array<Real, springClassCount> damping{};   ///< N s/m
};

class SpringSet
{
public:
    SpringSet();
    /// The springs of a built topology at its rest lengths, with no stiffness or damping yet.
    explicit SpringSet(SpringTopology topology);

    /// Appends a spring at rest length `rest`, with no stiffness or damping yet (lattice builders, tests). A shared
    /// topology is copied first, and the row plan, which no longer matches, is dropped.
    void add(Index a, Index b, Real rest, SpringClass cls);
    /// Gives the topology its row plan (buildLattice).
    void setRowPlan(std::shared_ptr<const SpringRowPlan> plan);

    std::size_t size() const { return m_topology->size(); }
    const SpringTopology& topology() const { return *m_topology; }
    std::shared_ptr<const SpringTopology> sharedTopology() const { return m_topology; }
    const std::vector<SpringEnds>& ends() const { return m_topology->ends; }
    const std::vector<SpringClass>& classes() const { return m_topology->springClass; }
    /// The springs at each of `massCount` masses; built on the first call (and again if springs were added since),
    /// from one thread, before kernels run in parallel, and shared by copies.
    const SpringAdjacency& adjacency(std::size_t massCount) const;
    /// The row plan, if the topology has one that fits `massCount` masses.
    const SpringRowPlan* rowPlan(std::size_t massCount) const;

    const std::vector<Real>& restLength() const { return m_restLength; } ///< m
    const std::vector<Real>& stiffness() const { return m_stiffness; }   ///< k_s, N/m
    const std::vector<Real>& damping() const { return m_damping; }       ///< k_d, N s/m
    /// Per-spring values to rewrite. Taking the stiffness or the damping drops the per-class summary.
    std::vector<Real>& mutableRestLength() { return m_restLength; }
    std::vector<Real>& mutableStiffness();
    std::vector<Real>& mutableDamping();

    /// Records that every spring of a class has its class's k_s and k_d, if they all do (bit for bit); otherwise
    /// leaves no summary. Called after the coefficients are set from the classes.
    void summariseUniformClasses();
    /// Each class's k_s and k_d when every spring has its class's, else null.
    const UniformClassCoefficients* uniformCoefficients() const { return m_uniform ? &*m_uniform : nullptr; }

private:
    /// Never changed in place while another set shares it: add() copies a shared topology first.
    SpringTopology& ownTopology();

    std::shared_ptr<SpringTopology> m_topology;
    std::vector<Real> m_restLength;
    std::vector<Real> m_stiffness;
    std::vector<Real> m_damping;
    std::optional<UniformClassCoefficients> m_uniform;
    mutable std::shared_ptr<const SpringAdjacency> m_adjacency;
};
} // namespace masse
