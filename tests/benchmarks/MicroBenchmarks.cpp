// Google Benchmark micro-benchmarks of the engine's kernels: `build/bin/masse_benchmarks` prints their figures.
// They time; they do not assert (speed is reported, not tested). Their sheets come from the bench scenes in
// data/scenes (bench-free-fall.json, bench-contact.json), at the size each benchmark names, so what they time can be
// watched with `masse view`. Each binds a pool of $MASSE_THREADS (else every core) threads for the kernels it calls
// directly, as the `masse` command would give a scene.

#include "support/TestThreads.h"

#include "scene/Scene.h"
#include "scene/SceneOverrides.h"

#include "core/contact/ContactSolver.h"
#include "core/forces/Damping.h"
#include "core/forces/Forces.h"
#include "core/integrate/Integrator.h"
#include "core/linear/CholeskyPreconditioner.h"
#include "core/linear/ConjugateGradient.h"
#include "core/linear/NestedDissection.h"
#include "core/linear/SlotMatrix.h"

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
    const test::BoundPool threads;
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
    const test::BoundPool threads;
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

/// A matrix of the implicit step's shape for the paper's sheet of `size`: a dense 3x3 block per spring,
/// h^2 k (n n^T + I / 10), and the masses on the diagonal.
SlotMatrix<3> implicitShapedMatrix(const MassSpringSystem& sheet)
{
    const Particles& p = sheet.particles;
    SlotMatrix<3> matrix;
    matrix.build(sheet.massCount(), sheet.springs.ends());
    for (std::size_t i = 0; i < sheet.massCount(); ++i)
    {
        matrix.add(matrix.diagonal(i), p.mass[i] * Mat3::Identity());
    }
    for (std::size_t s = 0; s < sheet.springs.size(); ++s)
    {
        const SpringEnds& e = sheet.springs.ends()[s];
        const Vec3 n = (p.position[e.a] - p.position[e.b]).normalized();
        const Mat3 block = (paperTimeStep * paperTimeStep * sheet.springs.stiffness()[s]) *
                           (n * n.transpose() + 0.1 * Mat3::Identity());
        matrix.add(matrix.diagonal(e.a), block);
        matrix.add(matrix.diagonal(e.b), block);
        matrix.add(matrix.ab(s), -block);
        matrix.add(matrix.ba(s), -block);
    }
    return matrix;
}

/// Analyses `matrix` (of `sheet`'s shape) in the sheet's nested-dissection order, as the implicit step does.
void analyseForSheet(CholeskyPreconditioner& preconditioner, const MassSpringSystem& sheet, const SlotMatrix<3>& matrix)
{
    preconditioner.analyse(matrix.matrix(), nestedDissection(sheet.particles.position, sheet.springs,
                                                             CholeskyPreconditioner::parallelDepth));
}

/// One refactorisation of the implicit step's preconditioner (CholeskyPreconditioner::refresh: the values put in the
/// factor's order, the staged LDL^T, the solves' copy of the factor) on a matrix of the step's shape. A drape-forming
/// run at 128x2x128 refactors some dozens of times as its material softens and its contacts change.
void choleskyRefresh(benchmark::State& state)
{
    const test::BoundPool threads;
    const MassSpringSystem sheet = paperSheet(int(state.range(0)));
    const SlotMatrix<3> matrix = implicitShapedMatrix(sheet);
    CholeskyPreconditioner preconditioner;
    analyseForSheet(preconditioner, sheet, matrix);
    for (auto _ : state)
    {
        if (!preconditioner.refresh(matrix.matrix()))
        {
            state.SkipWithError("the matrix is not positive definite");
            break;
        }
    }
    state.counters["rows"] = double(matrix.matrix().rows());
    state.counters["updates/entry"] = preconditioner.updatesPerEntry();
}
BENCHMARK(choleskyRefresh)->Arg(32)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond)->MinTime(2.0);

/// One application of that preconditioner (CholeskyPreconditioner::apply: the two triangular solves, each of which
/// streams the factor's copy): what every conjugate-gradient iteration of an implicit step costs besides the product.
void choleskyApply(benchmark::State& state)
{
    const test::BoundPool threads;
    const MassSpringSystem sheet = paperSheet(int(state.range(0)));
    const SlotMatrix<3> matrix = implicitShapedMatrix(sheet);
    CholeskyPreconditioner preconditioner;
    analyseForSheet(preconditioner, sheet, matrix);
    if (!preconditioner.refresh(matrix.matrix()))
    {
        state.SkipWithError("the matrix is not positive definite");
        return;
    }
    Eigen::VectorX<Real> r(matrix.matrix().rows());
    for (Eigen::Index i = 0; i < r.size(); ++i)
    {
        r[i] = Real((i * 37) % 101) / 101 - Real(0.5);
    }
    Eigen::VectorX<Real> z(r.size());
    for (auto _ : state)
    {
        preconditioner.apply(r, z);
        benchmark::DoNotOptimize(z.data());
    }
    state.counters["rows"] = double(r.size());
}
BENCHMARK(choleskyApply)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond)->MinTime(1.0);

/// The conjugate gradient's product with the implicit matrix, on one thread: argument 0 finds each mass's three rows by
/// comparing their columns (multiplySymmetricRows), 1 is told they come in threes (multiplyMassRows).
void implicitProduct(benchmark::State& state)
{
    const MassSpringSystem sheet = paperSheet(int(state.range(0)));
    const SlotMatrix<3> matrix = implicitShapedMatrix(sheet);
    const SparseMatrix& a = matrix.matrix();
    Eigen::VectorX<Real> x(a.rows());
    for (Eigen::Index i = 0; i < x.size(); ++i)
    {
        x[i] = Real((i * 37) % 101) / 101 - Real(0.5);
    }
    Eigen::VectorX<Real> y(x.size());
    for (auto _ : state)
    {
        if (state.range(1) == 0)
        {
            multiplySymmetricRows(a, x, y, 0, a.rows());
        }
        else
        {
            multiplyMassRows(a, x, y, 0, a.rows());
        }
        benchmark::DoNotOptimize(y.data());
    }
    state.counters["rows"] = double(a.rows());
}
BENCHMARK(implicitProduct)->Args({64, 0})->Args({64, 1})->Args({128, 0})->Args({128, 1})->Unit(benchmark::kMicrosecond);

/// One frame's contact for the sheet resting on two boxes (bench-contact.json): detection (Bullet's broadphase,
/// then face planes or GJK for every mass), one projection pass and the frame's end.
void contactDetection(benchmark::State& state)
{
    const test::BoundPool threads;
    scene::Scene scene(benchScene("bench-contact.json", int(state.range(0))));
    MassSpringSystem sheet = scene.system();
    ContactSolver& contact = scene.contact();
    StepContext context;
    for (auto _ : state)
    {
        contact.detect(sheet, context, 0, paperTimeStep, false);
        contact.project(sheet, context, paperTimeStep);
        contact.sweepAndReport(sheet, context, paperTimeStep);
    }
    state.counters["planes"] = double(contact.planeCount());
}
BENCHMARK(contactDetection)->Arg(64)->Arg(128)->Unit(benchmark::kMillisecond);
} // namespace

BENCHMARK_MAIN();
