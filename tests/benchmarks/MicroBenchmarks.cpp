// Google Benchmark micro-benchmarks of the engine's kernels: `build/bin/masse_benchmarks` prints their figures.
// They time; they do not assert (speed is reported, not tested).

#include "bridge/BulletEnvironment.h"

#include "core/ContactSolver.h"
#include "core/Damping.h"
#include "core/Forces.h"
#include "core/Integrator.h"
#include "core/Lattice.h"

#include <benchmark/benchmark.h>

using namespace masse;

namespace
{
MassSpringSystem paperSheet(int n)
{
    LatticeSpec spec;
    spec.countX = n;
    spec.countZ = n;
    MassSpringSystem sheet = makeSheet(buildLattice(spec), SheetParams{});
    sheet.forces.airDamping = airDampingRate(paperAirRetention, paperTimeStep);
    for (Vec3& x : sheet.particles.position)
    {
        x *= 1.001; // slightly stretched, so every spring does its full work
    }
    return sheet;
}

void springForces(benchmark::State& state)
{
    const MassSpringSystem sheet = paperSheet(int(state.range(0)));
    std::vector<Vec3> force(sheet.massCount(), Vec3::Zero());
    for (auto _ : state)
    {
        accumulateSpringForces(sheet.springs, 0, sheet.particles.position, sheet.particles.velocity, force);
        benchmark::DoNotOptimize(force.data());
    }
    state.counters["spring_steps_per_second"] =
        benchmark::Counter(double(sheet.springCount()), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(springForces)->Arg(64)->Arg(128)->Arg(256)->Unit(benchmark::kMillisecond);

void implicitStep(benchmark::State& state)
{
    MassSpringSystem sheet = paperSheet(int(state.range(0)));
    auto integrator = makeIntegrator(IntegratorKind::ImplicitEuler);
    integrator->step(sheet, paperTimeStep); // builds the sparsity pattern
    for (auto _ : state)
    {
        integrator->step(sheet, paperTimeStep);
    }
    state.counters["masses"] = double(sheet.massCount());
}
BENCHMARK(implicitStep)->Arg(32)->Arg(64)->Unit(benchmark::kMillisecond);

/// One frame's detection for a sheet resting on a box: Bullet's broadphase and GJK for every mass.
void contactDetection(benchmark::State& state)
{
    MassSpringSystem sheet = paperSheet(int(state.range(0)));
    bridge::BulletEnvironment environment;
    bridge::ObstacleSpec box;
    box.name = "box";
    box.halfExtents = Vec3(1, 0.5, 1);
    box.position = Vec3(0.3, 0.3 - 0.01 - 0.5, 0.3);
    environment.addObstacle(box);
    ContactSolver contact(environment, ContactSettings{});
    for (auto _ : state)
    {
        contact.beginFrame(sheet, 0, paperTimeStep, false);
        contact.afterSubstep(sheet, paperTimeStep);
        contact.endFrame(sheet, paperTimeStep);
    }
    state.counters["planes"] = double(contact.planeCount());
}
BENCHMARK(contactDetection)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond);
} // namespace

BENCHMARK_MAIN();
