/// The spring runs the force kernel walks (core/SpringRuns.h): every spring covered once as a spring run and once from
/// each end as a mass run, each mass's springs in increasing offset, lattices giving long runs; and the kernel's forces
/// against a plain scatter over the same springs.

#include "core/Forces.h"
#include "core/Lattice.h"
#include "core/MassSpringSystem.h"
#include "core/SpringForce.h"
#include "core/SpringRuns.h"

#include <gtest/gtest.h>

#include <map>
#include <random>

using namespace masse;

namespace
{
/// Checks the runs' invariants against the spring ends they were built from.
void expectRunsCover(const std::vector<SpringEnds>& ends, std::size_t massCount)
{
    const SpringRuns runs = buildSpringRuns(ends, massCount);
    // Spring runs: each spring once, with its own ends.
    std::vector<int> seen(ends.size(), 0);
    for (const SpringRun& run : runs.springRuns)
    {
        for (Index t = 0; t < run.count; ++t)
        {
            const std::size_t s = run.firstSpring + t;
            ++seen[s];
            EXPECT_EQ(ends[s].a, run.firstMass + t);
            EXPECT_EQ(std::int64_t(ends[s].b), std::int64_t(run.firstMass + t) + run.otherOffset);
        }
    }
    for (std::size_t s = 0; s < ends.size(); ++s)
    {
        EXPECT_EQ(seen[s], 1) << "spring " << s;
    }
    // Mass runs: each spring seen from each of its ends once; a mass's ranks in increasing offset.
    std::map<std::pair<std::size_t, std::size_t>, int> fromEnd; // (spring, mass) -> count
    std::vector<std::map<std::size_t, std::int64_t>> offsetAtRank(massCount);
    for (std::size_t rank = 0; rank < runs.rankCount(); ++rank)
    {
        Index previousEnd = 0;
        for (std::size_t r = runs.rankStart[rank]; r < runs.rankStart[rank + 1]; ++r)
        {
            const SpringRun& run = runs.runs[r];
            EXPECT_GE(run.firstMass, previousEnd) << "runs of one rank sorted and disjoint";
            previousEnd = run.firstMass + run.count;
            for (Index t = 0; t < run.count; ++t)
            {
                const std::size_t mass = run.firstMass + t;
                const std::size_t s = run.firstSpring + t;
                const std::size_t other = std::size_t(std::int64_t(mass) + run.otherOffset);
                EXPECT_TRUE((ends[s].a == mass && ends[s].b == other) || (ends[s].b == mass && ends[s].a == other));
                ++fromEnd[{s, mass}];
                offsetAtRank[mass][rank] = run.otherOffset;
            }
        }
    }
    for (std::size_t s = 0; s < ends.size(); ++s)
    {
        EXPECT_EQ((fromEnd[{s, ends[s].a}]), 1) << "spring " << s << " from end a";
        EXPECT_EQ((fromEnd[{s, ends[s].b}]), 1) << "spring " << s << " from end b";
    }
    for (std::size_t mass = 0; mass < massCount; ++mass)
    {
        std::int64_t previous = std::numeric_limits<std::int64_t>::min();
        std::size_t expectedRank = 0;
        for (const auto& [rank, offset] : offsetAtRank[mass])
        {
            EXPECT_EQ(rank, expectedRank++) << "mass " << mass << " has no gap in its ranks";
            EXPECT_GE(offset, previous) << "mass " << mass << " sums its springs in increasing offset";
            previous = offset;
        }
    }
}

/// A random spring set over `massCount` masses, placed in a jittered cube.
std::vector<SpringEnds> randomEnds(std::size_t massCount, std::size_t springCount, unsigned seed)
{
    std::mt19937 random(seed);
    std::uniform_int_distribution<Index> pick(0, Index(massCount - 1));
    std::vector<SpringEnds> ends;
    while (ends.size() < springCount)
    {
        const Index a = pick(random);
        const Index b = pick(random);
        if (a != b)
        {
            ends.push_back({a, b});
        }
    }
    return ends;
}
} // namespace

TEST(SpringRuns, EveryLatticeSpringCoveredOnceFromEachEnd)
{
    for (Structure structure : {Structure::Square2D, Structure::SaMM, Structure::SLaMM, Structure::TRiMM})
    {
        LatticeSpec spec;
        spec.structure = structure;
        spec.countX = 7;
        spec.countZ = 5;
        spec.layers = structure == Structure::Square2D ? 1 : 3;
        const Lattice lattice = buildLattice(spec);
        SCOPED_TRACE(std::string(structureName(structure)));
        expectRunsCover(lattice.springs.ends, lattice.massCount());
    }
}

TEST(SpringRuns, IrregularSpringSetCoveredOnceFromEachEnd)
{
    expectRunsCover(randomEnds(50, 300, 3), 50);
}

TEST(SpringRuns, LatticeRowsMakeLongRuns)
{
    // The kernel's speed rests on long runs: on a 64x2x64 TRiMM sheet a mass run should span most of a row (63
    // masses). Random spring order would give runs of about one mass; the bound says the lattice order is in place.
    LatticeSpec spec;
    parseSize("64x2x64", spec);
    const Lattice lattice = buildLattice(spec);
    const SpringRuns& runs = lattice.springs.runs(lattice.massCount());
    const double massesPerRun = double(2 * lattice.springCount()) / double(runs.runs.size());
    const double springsPerRun = double(lattice.springCount()) / double(runs.springRuns.size());
    EXPECT_GT(massesPerRun, 30.0);
    EXPECT_GT(springsPerRun, 30.0);
}

TEST(SpringRuns, KernelMatchesAPlainScatterOnAnIrregularSpringSet)
{
    // The run kernel against the textbook loop force[a] += f, force[b] -= f over the same springs. The two sum each
    // mass's forces in different orders, so they agree to rounding: 1e-12 of the largest force.
    const std::size_t n = 40;
    MassSpringSystem system;
    std::mt19937 random(11);
    std::uniform_real_distribution<Real> coordinate(-0.1, 0.1);
    for (std::size_t i = 0; i < n; ++i)
    {
        system.particles.add(Vec3(coordinate(random), coordinate(random), coordinate(random)), 0.001);
        system.particles.velocity[i] = Vec3(coordinate(random), coordinate(random), coordinate(random));
    }
    for (const SpringEnds& e : randomEnds(n, 200, 5))
    {
        const Real length = (system.particles.position[e.a] - system.particles.position[e.b]).norm();
        // Alternately stretched and compressed by 10%, so the repulsion (below the rest length) takes part.
        const Real rest = system.springs.size() % 2 == 0 ? length * 0.9 : length * 1.1;
        system.springs.add(e.a, e.b, rest, SpringClass::Planar);
        system.springs.stiffness.back() = 50 + coordinate(random) * 100;
        system.springs.damping.back() = 0.01;
    }
    system.forces.gravity = Vec3(0, -9.81, 0);
    system.forces.repulsion = 1e-4;
    std::vector<Vec3> force;
    const std::vector<Vec3>& x = system.particles.position;
    const std::vector<Vec3>& v = system.particles.velocity;
    evaluateForces(system, x, v, force);

    std::vector<Vec3> expected(n);
    Real largest = 0;
    for (std::size_t i = 0; i < n; ++i)
    {
        expected[i] = system.particles.mass[i] * (system.forces.gravity - system.forces.airDamping * v[i]);
    }
    const SpringSet& springs = system.springs;
    for (std::size_t s = 0; s < springs.size(); ++s)
    {
        const Index a = springs.ends[s].a;
        const Index b = springs.ends[s].b;
        const Vec3 d = x[a] - x[b];
        const Real length = d.norm();
        const Vec3 unit = d / length;
        const Real magnitude = springForceMagnitude(length, (v[a] - v[b]).dot(unit), springs.stiffness[s],
                                                   springs.damping[s], springs.restLength[s], system.forces.repulsion);
        expected[a] += magnitude * unit;
        expected[b] -= magnitude * unit;
    }
    for (std::size_t i = 0; i < n; ++i)
    {
        largest = std::max(largest, expected[i].norm());
    }
    for (std::size_t i = 0; i < n; ++i)
    {
        EXPECT_LT((force[i] - expected[i]).norm(), 1e-12 * largest) << "mass " << i;
    }
}
