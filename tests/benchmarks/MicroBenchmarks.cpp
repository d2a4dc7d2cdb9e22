// Google Benchmark micro-benchmarks of the engine's kernels: `build/bin/masse_benchmarks` prints their figures.
// They time; they do not assert (speed is reported, not tested). Their sheets come from the bench scenes in
// data/scenes (bench-free-fall.json, bench-contact.json), at the size each benchmark names, so what they time can be
// watched with `masse view`.

#include "scene/Scene.h"
#include "scene/SceneOverrides.h"

#include "core/ContactSolver.h"
#include "core/Damping.h"
#include "core/Forces.h"
#include "core/Integrator.h"

#include <benchmark/benchmark.h>

#include <string>

using namespace masse;

namespace
{
/// A bench scene of data/scenes at n x 2 x n.
scene::SceneSpec benchScene(const std::string& name, int n)
{
    const std::string size = std::to_string(n) + "x2x" + std::to_string(n);
    return scene::loadScene(std::string(MASSE_SOURCE_DIR) + "/data/scenes/" + name,
                            {scene::parseKeyOverride("sheet.size=" + size)});
}

MassSpringSystem paperSheet(int n)
{
    scene::Scene scene(benchScene("bench-free-fall.json", n));
    MassSpringSystem sheet = scene.system();
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

/// One frame's contact for the sheet resting on two boxes (bench-contact.json): detection (Bullet's broadphase,
/// then face planes or GJK for every mass), one projection pass and the frame's end.
void contactDetection(benchmark::State& state)
{
    scene::Scene scene(benchScene("bench-contact.json", int(state.range(0))));
    MassSpringSystem sheet = scene.system();
    ContactSolver& contact = scene.contact();
    StepContext context;
    for (auto _ : state)
    {
        contact.beginFrame(sheet, context, 0, paperTimeStep, false);
        contact.afterSubstep(sheet, context, paperTimeStep);
        contact.endFrame(sheet, context, paperTimeStep);
    }
    state.counters["planes"] = double(contact.planeCount());
}
BENCHMARK(contactDetection)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond);
} // namespace

BENCHMARK_MAIN();
