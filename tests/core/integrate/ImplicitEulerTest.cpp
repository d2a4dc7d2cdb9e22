// Implicit Euler at the paper's step with the paper's stiffness, and static shapes against closed forms.

#include "support/TestSystems.h"

#include "core/StageObserver.h"
#include "core/forces/Damping.h"
#include "core/forces/Energy.h"
#include "core/forces/SimdPath.h"
#include "core/integrate/ImplicitSolve.h"
#include "core/integrate/ImplicitSpringTerms.h"
#include "core/integrate/VelocityConstraint.h"
#include "core/parallel/TaskPool.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

using namespace masse;
using namespace masse::test;

// Paper Table 1 in SI (90.2 N/m planar, 60.8 N/m inter-layer, 1 g masses, 3% air, 6% sheet damping) at the paper's
// dt = 0.03 s: a TRiMM 12x2x12 sheet hung from two corners stays finite and comes to rest. The explicit stable step
// for these values is about 1e-3 s, so this is 30 times past it, in one implicit step per frame.
TEST(ImplicitEuler, PaperSheetHungFromTwoCornersComesToRestAtPaperStep)
{
    LatticeSpec spec;
    spec.countX = 12;
    spec.countZ = 12;
    const Lattice lattice = buildLattice(spec);
    MassSpringSystem sheet = makeSheet(lattice, SheetParams{});
    sheet.forces.airDamping = airDampingRate(paperAirRetention, paperTimeStep);
    sheet.particles.setPinned(lattice.bottomCorners()[0], true);
    sheet.particles.setPinned(lattice.bottomCorners()[1], true);
    EXPECT_LT(estimateStability(sheet, IntegratorKind::SymplecticEuler, 1.0).stableStep, paperTimeStep / 10);

    SimulatorSettings settings;
    settings.integrator = IntegratorKind::ImplicitEuler;
    Simulator simulator(std::move(sheet), settings);
    Real peakKinetic = 0;
    simulate(simulator, 40.0, paperTimeStep,
             [&](const Simulator& s)
             {
                 EXPECT_EQ(s.substepCount(), std::uint64_t(std::llround(s.time() / paperTimeStep)));
                 peakKinetic = std::max(peakKinetic, kineticEnergy(s.system().particles));
             });
    const Real kinetic = kineticEnergy(simulator.system().particles);
    EXPECT_GT(peakKinetic, 1e-3); // it really swung: 265 g falling about a metre
    EXPECT_LT(kinetic, 1e-9 * peakKinetic + 1e-12) << "still moving after 40 s";
    // Hanging from the edge z = -0.2, the sheet lies below the pins, stretched a little along its own weight.
    for (const Vec3& x : simulator.system().particles.position)
    {
        EXPECT_LE(x.y(), 0.4 + 1e-9);
        EXPECT_GT(x.y(), 0.3 - 1.2);
    }
}

namespace
{
/// Elastic catenary (Irvine): a cable of unstretched length L0, weight w per unstretched length and axial stiffness
/// EA hangs between supports a span D apart at equal height. p is unstretched arc length from the lowest point.
struct ElasticCatenary
{
    Real w;
    Real ea;
    Real horizontalTension = 0;

    Real x(Real p) const
    {
        const Real h = horizontalTension;
        const Real sign = p < 0 ? -1.0 : 1.0;
        p = std::abs(p);
        return sign * ((h / w) * std::asinh(w * p / h) + h * p / ea);
    }
    Real y(Real p) const
    {
        const Real h = horizontalTension;
        return std::sqrt((h / w) * (h / w) + p * p) + w * p * p / (2 * ea);
    }
    /// Finds the horizontal tension that makes the cable span D (x is increasing in H): bisection.
    void solveSpan(Real halfLength, Real halfSpan)
    {
        Real lo = 1e-12;
        Real hi = 1e6;
        for (int i = 0; i < 200; ++i)
        {
            horizontalTension = 0.5 * (lo + hi);
            (x(halfLength) > halfSpan ? hi : lo) = horizontalTension;
        }
    }
};
} // namespace

// A chain of 40 springs hung by its ends settles (implicit Euler, paper step) into the elastic catenary: every mass
// within 1% of the span of its closed-form place at the same unstretched arc length.
TEST(ImplicitEuler, HangingChainSettlesIntoElasticCatenary)
{
    const int segments = 40;
    const Real length = 1.0;
    const Real span = 0.8;
    const Real spacing = length / segments;
    const Real mass = 0.001;
    const Real k = 90.2;
    MassSpringSystem chain = makeChain(segments + 1, mass, k, spacing);
    chain.forces.gravity = Vec3(0, -standardGravity, 0);
    chain.forces.airDamping = airDampingRate(paperAirRetention, paperTimeStep);
    for (int j = 0; j <= segments; ++j)
    {
        chain.particles.position[std::size_t(j)] = Vec3(span * j / segments, 0, 0); // straight, compressed
    }
    chain.particles.setPinned(0, true);
    chain.particles.setPinned(Index(segments), true);

    SimulatorSettings settings;
    settings.integrator = IntegratorKind::ImplicitEuler;
    Simulator simulator(std::move(chain), settings);
    simulate(simulator, 60.0, paperTimeStep, [](const Simulator&) {});

    ElasticCatenary cable{mass * standardGravity / spacing, k * spacing};
    cable.solveSpan(length / 2, span / 2);
    Real worst = 0;
    for (int j = 0; j <= segments; ++j)
    {
        const Real p = j * spacing - length / 2;
        const Vec3 expected(span / 2 + cable.x(p), cable.y(p) - cable.y(length / 2), 0);
        const Vec3 actual = simulator.system().particles.position[std::size_t(j)];
        worst = std::max(worst, (actual - expected).norm());
    }
    EXPECT_LT(worst, 0.01 * span);
    // The sag is real (about a quarter of the span), so the 1% check is not trivially met by a straight line.
    const Real sag = -simulator.system().particles.position[segments / 2].y();
    EXPECT_GT(sag, 0.2 * span);
    RecordProperty("worst_error_over_span", std::to_string(worst / span));
    std::printf("catenary: worst error %.3g of the span, sag %.4f m\n", worst / span, sag);
}

namespace
{
/// The Table 1 sheet hung from two corners, run for `duration` with the given preconditioner; final positions.
std::vector<Vec3> hungSheetPositions(PreconditionerKind preconditioner, Real duration, SolverTally* tally = nullptr,
                                     int size = 12)
{
    Lattice lattice;
    MassSpringSystem sheet = paperSheet(size, &lattice);
    sheet.particles.setPinned(lattice.bottomCorners()[0], true);
    sheet.particles.setPinned(lattice.bottomCorners()[1], true);
    SimulatorSettings settings;
    settings.integrator = IntegratorKind::ImplicitEuler;
    settings.implicit.preconditioner = preconditioner;
    Simulator simulator(std::move(sheet), settings);
    simulate(simulator, duration, paperTimeStep, [](const Simulator&) {});
    if (tally)
    {
        *tally = simulator.solverTally();
    }
    return simulator.system().particles.position;
}
} // namespace

// The conjugate gradient's residual is held to the impulse of what drives the sheet: its weight, or its applied loads
// where they are larger (a forming pressure is one). A load of 1000 times the sheet's weight applied as forces on its
// masses, and the same load as a gravity 1001 times as strong, are the same system: with the diagonal preconditioner
// (so that every decade of residual costs iterations) the hung sheet's first second takes the same iterations either
// way, within one a step (measured: 75.4 both). Holding the applied load to the weight alone takes 23.6 more a step
// (99.0).
TEST(ImplicitEuler, TheResidualIsHeldToTheAppliedLoadsAsToTheWeight)
{
    const Real factor = 1000;
    auto iterations = [&](bool asForces)
    {
        Lattice lattice;
        MassSpringSystem sheet = paperSheet(12, &lattice);
        sheet.particles.setPinned(lattice.bottomCorners()[0], true);
        sheet.particles.setPinned(lattice.bottomCorners()[1], true);
        if (asForces)
        {
            for (std::size_t i = 0; i < sheet.particles.size(); ++i)
            {
                sheet.particles.externalForce[i] = factor * sheet.particles.mass[i] * sheet.forces.gravity;
            }
        }
        else
        {
            sheet.forces.gravity *= 1 + factor;
        }
        SimulatorSettings settings;
        settings.integrator = IntegratorKind::ImplicitEuler;
        settings.implicit.preconditioner = PreconditionerKind::Jacobi;
        Simulator simulator(std::move(sheet), settings);
        simulate(simulator, 1.0, paperTimeStep, [](const Simulator&) {});
        EXPECT_EQ(simulator.solverTally().capHits, 0u);
        return simulator.solverTally().meanIterations();
    };
    const Real loads = iterations(true);
    const Real heavier = iterations(false);
    EXPECT_NEAR(loads, heavier, 1.0);
    std::printf("iterations a step: load as forces %.2f, as gravity %.2f\n", loads, heavier);
}

// Near its equilibrium a sheet's right-hand side falls far below its weight's impulse, and the residual is held to a
// hundredth of that impulse there (ImplicitSolve::residualScale), not to the vanishing right-hand side. The hung
// Table 1 sheet, come to rest over 20 s and run 5 s more, solved with the diagonal preconditioner (every decade of
// residual costs iterations): its resting shape is the one a solve to a tolerance of 1e-10 gives, within 1e-7 m of a
// sag of 1.03 m (measured: 4.4e-9 m), in under a third of the iterations over the last 5 s (measured: 9.8 against
// 67.1 a step; held to the right-hand side, 81.9).
TEST(ImplicitEuler, ASheetAtRestIsBalancedToAHundredthOfItsWeightsImpulse)
{
    struct Rest
    {
        std::vector<Vec3> positions;
        Real iterationsAtRest = 0; ///< a step, over the last 5 s
        Real sag = 0;
    };
    auto hang = [](Real tolerance)
    {
        Lattice lattice;
        MassSpringSystem sheet = paperSheet(12, &lattice);
        sheet.particles.setPinned(lattice.bottomCorners()[0], true);
        sheet.particles.setPinned(lattice.bottomCorners()[1], true);
        SimulatorSettings settings;
        settings.integrator = IntegratorKind::ImplicitEuler;
        settings.implicit.preconditioner = PreconditionerKind::Jacobi;
        settings.implicit.tolerance = tolerance;
        Simulator simulator(std::move(sheet), settings);
        simulate(simulator, 20.0, paperTimeStep, [](const Simulator&) {});
        const SolverTally before = simulator.solverTally();
        simulate(simulator, 5.0, paperTimeStep, [](const Simulator&) {});
        const SolverTally after = simulator.solverTally();
        EXPECT_EQ(after.capHits, 0u);
        Rest rest;
        rest.positions = simulator.system().particles.position;
        rest.iterationsAtRest = Real(after.iterations - before.iterations) / Real(after.solves - before.solves);
        Real top = -std::numeric_limits<Real>::infinity();
        Real bottom = std::numeric_limits<Real>::infinity();
        for (const Vec3& x : rest.positions)
        {
            top = std::max(top, x.y());
            bottom = std::min(bottom, x.y());
        }
        rest.sag = top - bottom;
        return rest;
    };
    const Rest shipped = hang(ImplicitSettings{}.tolerance);
    const Rest tight = hang(1e-10);
    Real worst = 0;
    for (std::size_t i = 0; i < shipped.positions.size(); ++i)
    {
        worst = std::max(worst, (shipped.positions[i] - tight.positions[i]).norm());
    }
    EXPECT_GT(shipped.sag, 0.1) << "the sheet should hang";
    EXPECT_LT(worst, 1e-7);
    EXPECT_LT(shipped.iterationsAtRest, tight.iterationsAtRest / 3);
    std::printf("at rest: %.3g m from the tight solve's shape (sag %.3f m), %.1f iterations a step against %.1f\n",
                worst, shipped.sag, shipped.iterationsAtRest, tight.iterationsAtRest);
}

// Springs that join the same two masses share their blocks of the step's matrix, which the assembly must add, not
// overwrite: a sagging chain whose every link is three springs of k (one listed the other way round) moves as the
// chain of single 3k links, within 1e-9 m after 2 s (each solve is converged far below that on 27 unknowns; with the
// extra springs' blocks dropped from the coupling it sags centimetres apart).
TEST(ImplicitEuler, SpringsJoiningTheSameMassesAddUp)
{
    auto sag = [](bool tripled)
    {
        const int count = 9;
        const Real k = 90.2;
        const Real damping = 0.05;
        MassSpringSystem chain = makeChain(count, 0.001, tripled ? k : 3 * k, 0.1, tripled ? damping : 3 * damping);
        if (tripled)
        {
            for (int i = 0; i + 1 < count; ++i)
            {
                for (const auto& [a, b] : {std::pair{i, i + 1}, std::pair{i + 1, i}})
                {
                    chain.springs.add(Index(a), Index(b), 0.1, SpringClass::Planar);
                    chain.springs.mutableStiffness().back() = k;
                    chain.springs.mutableDamping().back() = damping;
                }
            }
        }
        chain.forces.gravity = Vec3(0, -standardGravity, 0);
        for (int j = 0; j < count; ++j)
        {
            chain.particles.position[std::size_t(j)] = Vec3(0.7 * j / (count - 1), 0, 0);
        }
        chain.particles.setPinned(0, true);
        chain.particles.setPinned(Index(count - 1), true);
        SimulatorSettings settings;
        settings.integrator = IntegratorKind::ImplicitEuler;
        Simulator simulator(std::move(chain), settings);
        simulate(simulator, 2.0, paperTimeStep, [](const Simulator&) {});
        return simulator.system().particles.position;
    };
    const std::vector<Vec3> tripled = sag(true);
    const std::vector<Vec3> single = sag(false);
    Real worst = 0;
    for (std::size_t i = 0; i < tripled.size(); ++i)
    {
        worst = std::max(worst, (tripled[i] - single[i]).norm());
    }
    EXPECT_LT(worst, 1e-9);
    EXPECT_LT(single[4].y(), -0.01) << "the chain should sag";
    std::printf("chain of tripled links against single 3k links after 2 s: worst difference %.3g m, sag %.4g m\n",
                worst, -single[4].y());
}

// The same with constrained masses: the constraints' terms of the right-hand side (b - A c) and their reactions read
// each pair's shared block once, whichever of its springs they come to. One implicit step of a chain of nine stretched
// links, one mass held in every direction at a speed and one held along a slanted normal, is the same step (every
// velocity change and reaction within 1e-12 of it) whether each link is one spring of 3k or three of k.
TEST(ImplicitSolve, ConstrainedMassesSeeSpringsJoiningTheSameMassesOnce)
{
    struct Step
    {
        std::vector<Vec3> deltaV;
        std::vector<Vec3> reactions;
    };
    auto step = [](bool tripled)
    {
        const int count = 9;
        const Real k = 90.2;
        MassSpringSystem chain = makeChain(count, 0.001, tripled ? k : 3 * k, 0.1);
        if (tripled)
        {
            for (int i = 0; i + 1 < count; ++i)
            {
                for (const auto& [a, b] : {std::pair{i, i + 1}, std::pair{i + 1, i}})
                {
                    chain.springs.add(Index(a), Index(b), 0.1, SpringClass::Planar);
                    chain.springs.mutableStiffness().back() = k;
                }
            }
        }
        for (int j = 0; j < count; ++j)
        {
            chain.particles.position[std::size_t(j)] = Vec3(0.12 * j, 0.01 * (j % 3), 0);
            chain.particles.force[std::size_t(j)] = Vec3(0, -0.001 * standardGravity, 0);
        }
        std::vector<VelocityConstraint> constraints(2);
        constraints[0].mass = 3;
        constraints[0].directions = 3;
        constraints[0].velocity = Vec3(0.1, -0.2, 0.05);
        constraints[1].mass = 6;
        constraints[1].normal = Vec3(1, 2, 0).normalized();
        constraints[1].velocity = Vec3(0.3, 0.1, 0);
        ImplicitSettings settings;
        settings.tolerance = 1e-14;
        ImplicitSolve solve(settings, false);
        solve.solve(chain, constraints, 0.03 * 0.03, {}, {});
        Step result;
        for (int j = 0; j < count; ++j)
        {
            result.deltaV.push_back(solve.deltaV(Index(j)));
        }
        result.reactions = {constraints[0].reaction, constraints[1].reaction};
        return result;
    };
    const Step tripled = step(true);
    const Step single = step(false);
    Real worstDeltaV = 0;
    for (std::size_t j = 0; j < single.deltaV.size(); ++j)
    {
        worstDeltaV = std::max(worstDeltaV, (tripled.deltaV[j] - single.deltaV[j]).norm());
    }
    Real worstReaction = 0;
    for (std::size_t c = 0; c < single.reactions.size(); ++c)
    {
        worstReaction = std::max(worstReaction, (tripled.reactions[c] - single.reactions[c]).norm());
    }
    EXPECT_LT(worstDeltaV, 1e-12);
    EXPECT_LT(worstReaction, 1e-12);
    EXPECT_GT(single.deltaV[4].norm(), 1e-3) << "the held masses pull the free ones";
    EXPECT_GT(single.reactions[0].norm(), 1e-5);
    std::printf("tripled links against single 3k links: velocity changes within %.3g m/s, reactions within %.3g N s\n",
                worstDeltaV, worstReaction);
}

// The reactions are gathered per constrained mass on the pool, in chunks of a thousand masses: a 40x2x40 sheet with
// some 1,500 constrained masses (every other: held in every direction, or along a slanted normal) gets the same
// velocity changes and reactions, bit for bit, at one thread and at three.
TEST(ImplicitSolve, ReactionsAreTheSameBitsAtAnyThreadCount)
{
    const Lattice lattice = twoLayerTrimm(40, 0.2, 0.004);
    struct Step
    {
        std::vector<Vec3> deltaV;
        std::vector<Vec3> reactions;
    };
    auto step = [&](int threads)
    {
        TaskPool pool(threads);
        const PoolScope scope(pool);
        MassSpringSystem sheet = makeSheet(lattice, SheetParams{});
        for (std::size_t i = 0; i < sheet.particles.size(); ++i)
        {
            const Real phase = Real(i) * Real(0.37);
            sheet.particles.position[i] += Vec3(2e-3 * std::sin(phase), 3e-3 * std::cos(2 * phase), 0);
            sheet.particles.force[i] = Vec3(0, -1e-3 * standardGravity, 0);
        }
        std::vector<VelocityConstraint> constraints;
        for (Index i = 0; i < lattice.massCount(); i += 2)
        {
            VelocityConstraint& c = constraints.emplace_back();
            c.mass = i;
            if (i % 4 == 0)
            {
                c.directions = 3;
                c.velocity = Vec3(0.01, -0.02, 0.005);
            }
            else
            {
                c.normal = Vec3(0.3, 1, -0.2).normalized();
                c.velocity = Vec3(0, -0.05, 0);
            }
        }
        ImplicitSolve solve(ImplicitSettings{}, false);
        solve.solve(sheet, constraints, 0.03 * 0.03, {}, {});
        Step result;
        for (Index i = 0; i < lattice.massCount(); ++i)
        {
            result.deltaV.push_back(solve.deltaV(i));
        }
        for (const VelocityConstraint& c : constraints)
        {
            result.reactions.push_back(c.reaction);
        }
        return result;
    };
    const Step one = step(1);
    const Step three = step(3);
    ASSERT_GT(one.reactions.size(), 1500u); // two chunks of the reactions' gather
    EXPECT_EQ(one.deltaV, three.deltaV);
    EXPECT_EQ(one.reactions, three.reactions);
    Real largest = 0;
    for (const Vec3& r : one.reactions)
    {
        largest = std::max(largest, r.norm());
    }
    EXPECT_GT(largest, 1e-6) << "the constraints should press";
}

// The Cholesky-preconditioned solve gives the diagonal-preconditioned one's result to the tolerance: on the swinging
// sheet of the first test after 3 s (100 steps, each solved to a relative residual of 1e-5) every mass agrees within
// 1e-4 of the sheet's 1 m size, while the iteration counts differ by an order of magnitude.
TEST(ImplicitEuler, CholeskyPreconditionerAgreesWithDiagonal)
{
    SolverTally cholesky;
    SolverTally jacobi;
    const std::vector<Vec3> withFactor = hungSheetPositions(PreconditionerKind::Cholesky, 3.0, &cholesky);
    const std::vector<Vec3> withDiagonal = hungSheetPositions(PreconditionerKind::Jacobi, 3.0, &jacobi);
    Real worst = 0;
    for (std::size_t i = 0; i < withFactor.size(); ++i)
    {
        worst = std::max(worst, (withFactor[i] - withDiagonal[i]).norm());
    }
    EXPECT_LT(worst, 1e-4);
    EXPECT_EQ(cholesky.capHits, 0u);
    EXPECT_EQ(jacobi.capHits, 0u);
    // A drifted factor is kept while its extra iterations since it was made cost less than rebuilding it
    // (RefreshBudget): at this size a rebuild is worth 19 iterations (CholeskyPreconditioner::refreshCost), so a step
    // takes at most that beyond a fresh factor's two. Measured: largest 14, 18 rebuilds in the 100 steps.
    EXPECT_LE(cholesky.largestIterations, 2 + 19);
    EXPECT_LT(cholesky.meanIterations(), 0.5 * jacobi.meanIterations());
    // The tally counts the factor's rebuilds: the first step's, and one each time it drifted; the diagonal has none.
    EXPECT_GE(cholesky.refactorisations, 1u);
    EXPECT_LT(cholesky.refactorisations, cholesky.solves);
    EXPECT_EQ(jacobi.refactorisations, 0u);
    std::printf("Cholesky vs diagonal after 3 s: worst difference %.3g m; iterations mean %.2f (largest %d, %llu "
                "refactorisations in %llu steps) vs %.2f (largest %d)\n",
                worst, cholesky.meanIterations(), cholesky.largestIterations,
                static_cast<unsigned long long>(cholesky.refactorisations),
                static_cast<unsigned long long>(cholesky.solves), jacobi.meanIterations(), jacobi.largestIterations);
}

// The same for the multigrid preconditioner, on a sheet large enough for two levels (24x2x24, 1,105 masses): every
// mass within 1e-4 m of the diagonal-preconditioned result after 3 s, at most 20 iterations a step (measured: mean
// 9.9, largest 16, where the factor takes 7.5 and 9, the diagonal 106 and 136).
TEST(ImplicitEuler, MultigridPreconditionerAgreesWithDiagonal)
{
    SolverTally multigrid;
    SolverTally jacobi;
    const std::vector<Vec3> withCycle = hungSheetPositions(PreconditionerKind::Multigrid, 3.0, &multigrid, 24);
    const std::vector<Vec3> withDiagonal = hungSheetPositions(PreconditionerKind::Jacobi, 3.0, &jacobi, 24);
    Real worst = 0;
    for (std::size_t i = 0; i < withCycle.size(); ++i)
    {
        worst = std::max(worst, (withCycle[i] - withDiagonal[i]).norm());
    }
    EXPECT_LT(worst, 1e-4);
    EXPECT_EQ(multigrid.capHits, 0u);
    EXPECT_EQ(jacobi.capHits, 0u);
    EXPECT_LE(multigrid.largestIterations, 20);
    EXPECT_LT(multigrid.meanIterations(), 0.5 * jacobi.meanIterations());
    std::printf("multigrid vs diagonal after 3 s: worst difference %.3g m; iterations mean %.2f (largest %d) vs %.2f "
                "(largest %d)\n",
                worst, multigrid.meanIterations(), multigrid.largestIterations, jacobi.meanIterations(),
                jacobi.largestIterations);
}

// The catenary of the test above with the diagonal preconditioner: the same shape (every mass within 1e-5 m).
TEST(ImplicitEuler, CatenaryIsTheSameWithEitherPreconditioner)
{
    auto settle = [](PreconditionerKind preconditioner)
    {
        MassSpringSystem chain = makeChainPinnedStraight();
        chain.forces.airDamping = airDampingRate(paperAirRetention, paperTimeStep);
        SimulatorSettings settings;
        settings.integrator = IntegratorKind::ImplicitEuler;
        settings.implicit.preconditioner = preconditioner;
        Simulator simulator(std::move(chain), settings);
        simulate(simulator, 20.0, paperTimeStep, [](const Simulator&) {});
        return simulator.system().particles.position;
    };
    const std::vector<Vec3> a = settle(PreconditionerKind::Cholesky);
    const std::vector<Vec3> b = settle(PreconditionerKind::Jacobi);
    const std::vector<Vec3> c = settle(PreconditionerKind::Multigrid);
    for (std::size_t i = 0; i < a.size(); ++i)
    {
        EXPECT_LT((a[i] - b[i]).norm(), 1e-5) << "mass " << i;
        EXPECT_LT((c[i] - b[i]).norm(), 1e-5) << "mass " << i;
    }
}

// Each spring's term of the implicit step (ImplicitSpringTerms) is, bit for bit and on every SIMD path, the term as
// Eigen's expressions give it: the stiffness block -K = axial n n^T + transverse (I - n n^T) (axial with the
// compressed spring's repulsion), the block a k_d n n^T + a^2 (-K), and a (-K) (a v_ab + offset_ab). A deformed,
// moving sheet, some springs stretched and some compressed.
TEST(ImplicitSpringTerms, AreEigensExpressionsBitForBitOnEveryPath)
{
    MassSpringSystem sheet = paperSheet(8);
    sheet.forces.repulsion = 1e-4;
    std::vector<Vec3> offset(sheet.particles.size());
    for (std::size_t i = 0; i < sheet.particles.size(); ++i)
    {
        const Real phase = Real(i % 13) / 13;
        sheet.particles.position[i] += Vec3(0.004 * std::sin(7 * phase), 0.003 * std::cos(5 * phase), -0.002 * phase);
        sheet.particles.velocity[i] = Vec3(0.3 * phase, -0.2, 0.1 * std::cos(3 * phase));
        offset[i] = Vec3(1e-4 * phase, 2e-4, -1e-4 * phase);
    }
    const Real a = 0.03;
    const SpringSet& springs = sheet.springs;
    const Particles& p = sheet.particles;
    SpringTermInputs inputs;
    inputs.a = a;
    inputs.offset = &offset;
    const SimdPathGuard simdGuard;
    for (const SimdPath path : supportedSimdPaths())
    {
        std::vector<SpringTerm> terms(springs.size());
        std::vector<std::uint8_t> engaged(springs.size());
        computeSpringTerms(path, sheet, inputs, 0, springs.size(), terms.data(), engaged.data());
        int compressed = 0;
        for (std::size_t s = 0; s < springs.size(); ++s)
        {
            const Index ea = springs.ends()[s].a;
            const Index eb = springs.ends()[s].b;
            const Vec3 d = p.position[ea] - p.position[eb];
            const Real length = d.norm();
            const Real rest = springs.restLength()[s];
            ASSERT_TRUE(engaged[s]);
            const Vec3 n = d / length;
            const Mat3 nn = n * n.transpose();
            Real axial = springs.stiffness()[s];
            if (length < rest)
            {
                axial += Real(2) * sheet.forces.repulsion / (length * length * length);
                ++compressed;
            }
            const Real transverse = springs.stiffness()[s] * std::max(Real(0), Real(1) - rest / length);
            const Mat3 stiffness = axial * nn + transverse * (Mat3::Identity() - nn);
            const Mat3 block = (a * springs.damping()[s]) * nn + a * a * stiffness;
            const Vec3 move = a * (p.velocity[ea] - p.velocity[eb]) + (offset[ea] - offset[eb]);
            const Vec3 kv = a * (stiffness * move);
            for (int r = 0; r < 3; ++r)
            {
                for (int c = 0; c < 3; ++c)
                {
                    ASSERT_EQ(terms[s].block()(r, c), block(r, c)) << simdPathName(path) << " spring " << s;
                }
                ASSERT_EQ(terms[s].kv[r], kv[r]) << simdPathName(path) << " spring " << s << " row " << r;
            }
        }
        EXPECT_GT(compressed, 0);
    }
}

namespace
{
/// Asks for every frame to be taken as `solves` and notes the frames it is given.
class SplitAsker final : public StepHook
{
public:
    explicit SplitAsker(int solves) : m_solves(solves) {}
    int solvesFor(MassSpringSystem& /*system*/, Real /*dt*/) override
    {
        ++asked;
        return m_solves;
    }
    void beginFrame(MassSpringSystem& /*system*/, StepContext& /*context*/, Real time, Real dt) override
    {
        frames.emplace_back(time, dt);
    }
    int asked = 0;
    std::vector<std::pair<Real, Real>> frames; ///< (start, length) of each frame begun

private:
    int m_solves;
};
} // namespace

// A hook that asks for a frame to be taken as three solves gets three frames of a third of dt, each begun at its own
// time, and the sheet ends with the bits of three steps of dt / 3 taken without the hook; the report sums their
// substeps. An explicit integrator is never asked (it substeps by its stability).
TEST(ImplicitEuler, AFrameAHookAsksToSplitIsTakenAsThatManySolves)
{
    const Real dt = paperTimeStep;
    SimulatorSettings settings;
    settings.integrator = IntegratorKind::ImplicitEuler;
    Simulator split(paperSheet(8), settings);
    SplitAsker asker(3);
    split.addHook(&asker);
    const StepReport report = split.step(dt);
    EXPECT_EQ(asker.asked, 1);
    ASSERT_EQ(asker.frames.size(), 3u);
    for (std::size_t k = 0; k < 3; ++k)
    {
        EXPECT_DOUBLE_EQ(asker.frames[k].second, dt / 3);
        EXPECT_NEAR(asker.frames[k].first, Real(k) * dt / 3, 1e-15);
    }
    EXPECT_EQ(report.substeps, 3);
    EXPECT_DOUBLE_EQ(report.substep, dt / 3);
    EXPECT_GT(report.solverIterations, 0);

    Simulator byThirds(paperSheet(8), settings);
    for (int k = 0; k < 3; ++k)
    {
        byThirds.step(dt / 3);
    }
    EXPECT_TRUE(sameBits(split.system().particles.position, byThirds.system().particles.position));
    EXPECT_TRUE(sameBits(split.system().particles.velocity, byThirds.system().particles.velocity));
    Simulator whole(paperSheet(8), settings);
    whole.step(dt);
    EXPECT_FALSE(sameBits(split.system().particles.position, whole.system().particles.position));

    settings.integrator = IntegratorKind::SymplecticEuler;
    Simulator explicitOne(paperSheet(8), settings);
    SplitAsker ignored(3);
    explicitOne.addHook(&ignored);
    explicitOne.step(dt);
    EXPECT_EQ(ignored.asked, 0);
    EXPECT_EQ(ignored.frames.size(), 1u);
}

// A mass under two constraints along different normals (a sheet's vertex resting on an obstacle's face and meeting a
// fold of its own sheet across it) leaves the solve with each normal's own velocity, and each constraint reads its own
// part of the reaction. One free mass of m = 2 g, no springs, force f, step a: the velocity along n_1 and n_2 is what
// each constraint asks, the free direction takes v_z = a f_z / m, and the reaction R = m dv - a f splits as
// R = r_1 n_1 + r_2 n_2 with r_i n_i each constraint's. With orthogonal and with 45-degree normals. Had the first
// constraint's velocity set every held direction, the velocity along n_2 would be 0.
TEST(ImplicitSolve, TwoConstraintsOnAMassEachHoldTheirOwnNormalsVelocity)
{
    const Real a = 0.03;
    const Real m = 0.002;
    const Vec3 force(0.01, -0.02, 0.03);
    const Vec3 wanted(1, 2, 0); // the velocity the two constraints ask for along their normals, in the x-y plane
    const Vec3 diagonal = Vec3(1, 1, 0).normalized();
    for (const Vec3& second : {Vec3(Vec3::UnitY()), diagonal})
    {
        SCOPED_TRACE(testing::Message() << "second normal " << second.transpose());
        MassSpringSystem one = makeChain(1, m, 1, 0.1);
        one.particles.force[0] = force;
        std::vector<VelocityConstraint> constraints(2);
        constraints[0].mass = 0;
        constraints[0].normal = Vec3::UnitX();
        constraints[0].velocity = Vec3(wanted.x(), 0, 0);
        constraints[1].mass = 0;
        constraints[1].normal = second;
        constraints[1].velocity = wanted.dot(second) * second; // only its normal component matters
        ImplicitSolve solve(ImplicitSettings{}, false);
        solve.solve(one, constraints, a, {}, {});
        const Vec3 dv = solve.deltaV(0);
        EXPECT_NEAR(dv.x(), wanted.x(), 1e-12);
        EXPECT_NEAR(dv.y(), wanted.y(), 1e-12);
        EXPECT_NEAR(dv.z(), a * force.z() / m, 1e-12);
        const Vec3 reaction = m * dv - a * force;
        EXPECT_NEAR((constraints[0].reaction + constraints[1].reaction - reaction).norm(), 0, 1e-12);
        EXPECT_NEAR(constraints[0].reaction.cross(Vec3::UnitX()).norm(), 0, 1e-12);
        EXPECT_NEAR(constraints[1].reaction.cross(second).norm(), 0, 1e-12);
    }
}

namespace
{
/// Every solver stage boundary it is told of, in order (true for a begin).
class SolverStageRecorder final : public StageObserver
{
public:
    struct Boundary
    {
        Stage stage;
        bool begin;
    };
    void begin(Stage stage) override { boundaries.push_back({stage, true}); }
    void end(Stage stage) override { boundaries.push_back({stage, false}); }
    int begun(Stage stage) const
    {
        return int(std::count_if(boundaries.begin(), boundaries.end(),
                                 [&](const Boundary& b) { return b.stage == stage && b.begin; }));
    }
    std::vector<Boundary> boundaries;
};
} // namespace

// The implicit solve tells a simulator's stage observer (StageObserver.h) where its time goes, for `masse bench` or a
// program's own profiler: the pattern's analysis once per topology, each solve's assembly, the preconditioner's
// refreshes and following, the iterations; each stage ends before the next begins. The observer stays with the
// simulator when it changes integrator: the explicit ones report no solver stages, a new implicit one its analysis
// again. Without an observer nothing is reported.
TEST(ImplicitEuler, TellsAStageObserverWhereItsSolvesGo)
{
    Lattice lattice;
    MassSpringSystem sheet = paperSheet(8, &lattice);
    sheet.particles.setPinned(lattice.bottomCorners()[0], true);
    SimulatorSettings settings;
    settings.integrator = IntegratorKind::ImplicitEuler;
    Simulator simulator(std::move(sheet), settings);
    SolverStageRecorder recorder;
    simulator.setStageObserver(&recorder);

    simulator.step(paperTimeStep);
    EXPECT_EQ(recorder.begun(Stage::SolverAnalysis), 1);
    EXPECT_GE(recorder.begun(Stage::SolverPreconditioner), 1); // the first factorisation
    EXPECT_GE(recorder.begun(Stage::SolverIterations), recorder.begun(Stage::SolverAssembly));
    EXPECT_GE(recorder.begun(Stage::SolverAssembly), 1);
    for (std::size_t k = 0; k < recorder.boundaries.size(); ++k)
    {
        const SolverStageRecorder::Boundary& b = recorder.boundaries[k];
        ASSERT_EQ(b.begin, k % 2 == 0) << "boundary " << k << ": stages are told one at a time, each begun then ended";
        if (!b.begin)
        {
            EXPECT_EQ(b.stage, recorder.boundaries[k - 1].stage) << "boundary " << k;
        }
    }
    recorder.boundaries.clear();
    simulator.step(paperTimeStep);
    EXPECT_EQ(recorder.begun(Stage::SolverAnalysis), 0); // the same topology
    EXPECT_GE(recorder.begun(Stage::SolverAssembly), 1);
    EXPECT_GE(recorder.begun(Stage::SolverIterations), 1);

    recorder.boundaries.clear();
    simulator.setIntegrator(IntegratorKind::SymplecticEuler);
    simulator.step(paperTimeStep);
    EXPECT_TRUE(recorder.boundaries.empty());
    simulator.setIntegrator(IntegratorKind::ImplicitEuler);
    simulator.step(paperTimeStep);
    EXPECT_EQ(recorder.begun(Stage::SolverAnalysis), 1);
    EXPECT_GE(recorder.begun(Stage::SolverIterations), 1);

    recorder.boundaries.clear();
    simulator.setStageObserver(nullptr);
    simulator.step(paperTimeStep);
    EXPECT_TRUE(recorder.boundaries.empty());
}
