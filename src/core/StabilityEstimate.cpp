#include "StabilityEstimate.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace masse
{
StabilityEstimate estimateStability(const MassSpringSystem& system, IntegratorKind kind, Real safety)
{
    StabilityEstimate estimate;
    const Particles& p = system.particles;
    const SpringSet& springs = system.springs;
    const Real infinity = std::numeric_limits<Real>::infinity();

    // Row sums of M^-1/2 K M^-1/2: k/m_a on the diagonal, k/sqrt(m_a m_b) off it. A pinned end has no degree of
    // freedom, so its inverse mass of zero drops its row and the coupling term.
    std::vector<Real> rowSum(p.size(), Real(0));
    Real minRatio = infinity; // smallest k_d / k
    Real maxRatio = 0;        // largest k_d / k
    const Real repulsion = system.forces.repulsion;
    for (std::size_t s = 0; s < springs.size(); ++s)
    {
        const Index a = springs.ends[s].a;
        const Index b = springs.ends[s].b;
        Real k = springs.stiffness[s];
        if (repulsion > 0)
        {
            // The repulsion stiffens a compressed spring by 2 k_r / l^3; count it at no less than half the rest
            // length, the range where contact and damping keep real sheets.
            const Real rest = springs.restLength[s];
            const Real length = std::max((p.position[a] - p.position[b]).norm(), Real(0.5) * rest);
            if (length < rest)
            {
                k += Real(2) * repulsion / (length * length * length);
            }
        }
        const Real wa = p.inverseMass[a];
        const Real wb = p.inverseMass[b];
        const Real coupling = std::sqrt(wa * wb);
        rowSum[a] += k * (wa + coupling);
        rowSum[b] += k * (wb + coupling);
        if (k > 0)
        {
            const Real ratio = springs.damping[s] / k;
            minRatio = std::min(minRatio, ratio);
            maxRatio = std::max(maxRatio, ratio);
        }
    }
    for (const UserSpring& spring : system.userSprings.all())
    {
        rowSum[spring.mass] += spring.stiffness * p.inverseMass[spring.mass];
    }
    const Real maxRow = rowSum.empty() ? Real(0) : *std::max_element(rowSum.begin(), rowSum.end());
    const Real w = std::sqrt(maxRow);
    estimate.highestFrequency = w;

    if (!isExplicit(kind) || w == 0)
    {
        estimate.stableStep = infinity;
        return estimate;
    }
    if (kind == IntegratorKind::ExplicitEuler)
    {
        if (minRatio > 0 && minRatio < infinity)
        {
            estimate.stableStep = safety * std::min(minRatio, Real(2) / (maxRatio * w * w));
        }
        else
        {
            estimate.stableStep = safety * Real(0.1) / w;
        }
    }
    else
    {
        const Real a = maxRatio;
        estimate.stableStep = safety * (std::sqrt(a * a + Real(4) / (w * w)) - a);
    }
    // Air drag alone: a step over 2/c would overshoot the drag's decay.
    if (system.forces.airDamping > 0)
    {
        estimate.stableStep = std::min(estimate.stableStep, safety * Real(2) / system.forces.airDamping);
    }
    return estimate;
}
} // namespace masse
