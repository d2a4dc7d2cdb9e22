#include "core/integrate/StabilityEstimate.h"

#include "core/InputError.h"
#include "core/NamedEnum.h"
#include "core/parallel/TaskPool.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace masse
{
namespace
{
/// Power iterations on the mass-weighted stiffness; the Rayleigh quotient of a lattice's dense top band is within a
/// few percent of the largest eigenvalue after this many (and never above it).
constexpr int stiffnessPowerIterations = 40;
/// What the power estimate of the highest frequency is raised by, for the part of the top band it has not reached.
constexpr Real powerMargin = 1.1;
constexpr std::size_t springChunk = 16384;

constexpr EnumName<StabilityMethod> stabilityMethodNames[] = {
    {StabilityMethod::Power, "power"},
    {StabilityMethod::Gershgorin, "gershgorin"},
};

/// A reproducible pseudo-random number in [-1, 1) for coordinate c of mass i (splitmix64): the start vector has a
/// component along every mode, whatever the lattice.
Real startComponent(std::size_t i, int c)
{
    std::uint64_t z = std::uint64_t(i) * 3 + std::uint64_t(c) + 0x9e3779b97f4a7c15ull;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
    z ^= z >> 31;
    return Real(z >> 11) * (Real(2) / Real(1ull << 53)) - Real(1);
}

/// The highest frequency (rad/s) of the sheet linearised at its current state, sqrt of the largest eigenvalue of
/// W^1/2 K W^1/2 (W the inverse masses, zero for pinned ones; K the springs' axial stiffness k n n^T plus their
/// geometric stiffness |k (1 - s/l)| (I - n n^T), and the user springs), by power iteration, raised by powerMargin.
/// Kernels over ranges: pass 1 computes each spring's force for the current vector, pass 2 gathers each mass's
/// through the adjacency, and the norms are summed chunk by chunk in chunk order, so the result does not depend on
/// the thread count.
Real powerFrequency(const MassSpringSystem& system)
{
    const Particles& p = system.particles;
    const SpringSet& springs = system.springs;
    const std::size_t n = p.size();
    const std::size_t m = springs.size();
    std::vector<Real> sqrtW(n);
    for (std::size_t i = 0; i < n; ++i)
    {
        sqrtW[i] = std::sqrt(p.inverseMass[i]);
    }
    std::vector<Vec3> direction(m);
    std::vector<Real> axial(m);
    std::vector<Real> geometric(m);
    parallelFor(m, springChunk,
                [&](std::size_t begin, std::size_t end)
                {
                    for (std::size_t s = begin; s < end; ++s)
                    {
                        const Vec3 d = p.position[springs.ends()[s].a] - p.position[springs.ends()[s].b];
                        const Real length = d.norm();
                        const Real k = springs.stiffness()[s];
                        direction[s] = length > 0 ? Vec3(d / length) : Vec3::UnitX();
                        axial[s] = k;
                        // A spring at zero length has no direction; its geometric part is then bounded by k
                        // (isotropic).
                        geometric[s] = length > 0 ? std::abs(k * (Real(1) - springs.restLength()[s] / length)) : k;
                    }
                });
    std::vector<Real> userStiffness(n, Real(0));
    for (const UserSpring& spring : system.userSprings.all())
    {
        userStiffness[spring.mass] += spring.stiffness;
    }
    const SpringAdjacency& adjacency = springs.adjacency(n);

    std::vector<Vec3> q(n);
    for (std::size_t i = 0; i < n; ++i)
    {
        q[i] = sqrtW[i] > 0 ? Vec3(startComponent(i, 0), startComponent(i, 1), startComponent(i, 2)) : Vec3::Zero();
    }
    std::vector<Vec3> springForce(m);
    std::vector<Vec3> y(n);
    const std::size_t chunks = chunkCount(n, massChunkSize);
    std::vector<Real> partialQY(chunks);
    std::vector<Real> partialYY(chunks);
    std::vector<Real> partialQQ(chunks);
    const auto sumInOrder = [](const std::vector<Real>& parts)
    {
        Real sum = 0;
        for (Real part : parts)
        {
            sum += part;
        }
        return sum;
    };
    // Normalise the start vector.
    parallelFor(n, massChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    Real qq = 0;
                    for (std::size_t i = begin; i < end; ++i)
                    {
                        qq += q[i].squaredNorm();
                    }
                    partialQQ[begin / massChunkSize] = qq;
                });
    const Real startNorm = std::sqrt(sumInOrder(partialQQ));
    if (!(startNorm > 0))
    {
        return 0; // every mass pinned
    }
    Real highest = 0;
    Real scale = Real(1) / startNorm;
    for (int iteration = 0; iteration < stiffnessPowerIterations; ++iteration)
    {
        // y = W^1/2 K W^1/2 (scale q): springs first, then each mass gathers its springs.
        parallelFor(m, springChunk,
                    [&](std::size_t begin, std::size_t end)
                    {
                        for (std::size_t s = begin; s < end; ++s)
                        {
                            const Index a = springs.ends()[s].a;
                            const Index b = springs.ends()[s].b;
                            const Vec3 dz = scale * (sqrtW[a] * q[a] - sqrtW[b] * q[b]);
                            const Vec3& u = direction[s];
                            const Real along = u.dot(dz);
                            springForce[s] = (axial[s] * along) * u + geometric[s] * (dz - along * u);
                        }
                    });
        parallelFor(n, massChunkSize,
                    [&](std::size_t begin, std::size_t end)
                    {
                        Real qy = 0;
                        Real yy = 0;
                        for (std::size_t i = begin; i < end; ++i)
                        {
                            Vec3 f = userStiffness[i] * (scale * sqrtW[i] * q[i]);
                            for (std::size_t k = adjacency.offsets[i]; k < adjacency.offsets[i + 1]; ++k)
                            {
                                const SpringAdjacency::Entry e = adjacency.entries[k];
                                if (springs.ends()[e.spring].a == Index(i))
                                {
                                    f += springForce[e.spring];
                                }
                                else
                                {
                                    f -= springForce[e.spring];
                                }
                            }
                            y[i] = sqrtW[i] * f;
                            qy += (scale * q[i]).dot(y[i]);
                            yy += y[i].squaredNorm();
                        }
                        partialQY[begin / massChunkSize] = qy;
                        partialYY[begin / massChunkSize] = yy;
                    });
        highest = std::max(highest, sumInOrder(partialQY)); // Rayleigh quotient of a unit vector
        const Real norm = std::sqrt(sumInOrder(partialYY));
        if (!(norm > 0))
        {
            break;
        }
        q.swap(y);
        scale = Real(1) / norm;
    }
    return std::sqrt(powerMargin * highest);
}
} // namespace

std::string_view stabilityMethodName(StabilityMethod method)
{
    return enumName(stabilityMethodNames, method);
}

StabilityMethod parseStabilityMethod(std::string_view name, std::string_view field)
{
    return parseEnum(stabilityMethodNames, name, field, "stability estimate");
}

StabilityEstimate estimateStability(const MassSpringSystem& system, IntegratorKind kind, Real safety,
                                    StabilityMethod method)
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
        const Index a = springs.ends()[s].a;
        const Index b = springs.ends()[s].b;
        Real k = springs.stiffness()[s];
        if (repulsion > 0)
        {
            // The repulsion stiffens a compressed spring by 2 k_r / l^3; count it at no less than half the rest
            // length, the range where contact and damping keep real sheets.
            const Real rest = springs.restLength()[s];
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
            const Real ratio = springs.damping()[s] / k;
            minRatio = std::min(minRatio, ratio);
            maxRatio = std::max(maxRatio, ratio);
        }
    }
    for (const UserSpring& spring : system.userSprings.all())
    {
        rowSum[spring.mass] += spring.stiffness * p.inverseMass[spring.mass];
    }
    const Real maxRow = rowSum.empty() ? Real(0) : *std::max_element(rowSum.begin(), rowSum.end());
    Real w = std::sqrt(maxRow);
    if (!isExplicit(kind) || w == 0)
    {
        estimate.highestFrequency = w;
        estimate.stableStep = infinity;
        return estimate;
    }
    // The Gershgorin bound is about twice the sheet's real highest frequency; the power estimate is tight. It
    // linearises at the current lengths, which the repulsion makes change quickly, so with repulsion the bound
    // stays.
    if (repulsion == 0 && method == StabilityMethod::Power)
    {
        w = std::min(w, powerFrequency(system));
    }
    estimate.highestFrequency = w;
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
