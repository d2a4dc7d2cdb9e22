/// `masse bench`: how fast the engine steps a scene (by default data/scenes/bench-free-fall.json, or bench-contact.json
/// with --contact: the benchmarks are scene files, so what is timed can be watched in the viewer), as one JSON line.
/// "steps" are steps of --dt, each split into "substeps" by the explicit integrators; "spring_steps_per_second"
/// (springs times substeps, divided by wall time) is the figure to compare across sizes, integrators and machines. Each
/// figure is the median of --repeat rounds. The rounds follow one untimed warm-up step; "setup_seconds" gives the
/// scene's construction and that first step apart (for the implicit integrators it holds the first factorisation).

#include "Commands.h"
#include "ScalarBaseline.h"
#include "SceneOptions.h"
#include "StageTimer.h"

#include "core/Format.h"
#include "core/InputError.h"
#include "core/Simulator.h"
#include "core/contact/ContactSolver.h"
#include "core/contact/EdgeContact.h"
#include "core/contact/SelfContact.h"
#include "core/forces/Forces.h"
#include "core/forces/SimdPath.h"
#include "core/material/ViscoelasticSprings.h"
#include "core/parallel/TaskPool.h"
#include "scene/MaterialFile.h"
#include "scene/Runner.h"
#include "scene/Scene.h"
#include "scene/SceneOverrides.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <iostream>
#include <limits>
#include <memory>
#include <numeric>
#include <vector>

namespace masse::app
{
namespace
{
struct BenchOptions
{
    std::string scene;     // a scene file; "" for data/scenes/bench-free-fall.json (bench-contact.json with --contact)
    std::string structure; // "" keeps the scene's
    std::string size;      // "" keeps the scene's
    std::string integrator;
    scene::EngineSettings engine;
    int steps = 5;
    int repeat = 5;
    std::string dt; // "" keeps the scene's (the paper's 0.03 s in the bench scenes)
    bool contact = false;
    bool baseline = false;
    std::string preconditioner;
    std::string material; // a material file: the sheet is made of it (2 mm thick) instead of Table 1's springs
    double temperatureC = 20;
    std::vector<std::string> settings; // --set KEY=VALUE
};

double median(std::vector<double> values)
{
    std::sort(values.begin(), values.end());
    return values[values.size() / 2];
}

/// The scene to time: the file given or the bench scene, with the flags' changes (each a --set of its key, so a bad
/// value is reported as the scene reader reports it).
scene::SceneSpec benchScene(const BenchOptions& options)
{
    if (!options.scene.empty() && options.contact)
    {
        throw InputError("--contact: chooses the contact bench scene (data/scenes/bench-contact.json); give either a "
                         "scene file or --contact");
    }
    const std::string path =
        !options.scene.empty()
            ? options.scene
            : dataDirectory() + (options.contact ? "/scenes/bench-contact.json" : "/scenes/bench-free-fall.json");
    std::vector<std::string> settings;
    if (!options.structure.empty())
    {
        settings.push_back("sheet.structure=" + options.structure);
    }
    if (!options.size.empty())
    {
        settings.push_back("sheet.size=" + options.size);
    }
    if (!options.integrator.empty())
    {
        settings.push_back("integrator.type=" + options.integrator);
    }
    if (!options.dt.empty())
    {
        settings.push_back("integrator.dt=" + options.dt);
    }
    if (!options.preconditioner.empty())
    {
        settings.push_back("integrator.preconditioner=" + options.preconditioner);
    }
    settings.insert(settings.end(), options.settings.begin(), options.settings.end());
    scene::SceneSpec spec = scene::loadScene(path, parseSettings(settings));
    if (!options.material.empty())
    {
        // A real 2 mm sheet (its layer spacing the thickness) at the given temperature, elastic: cold, its springs
        // are thousands of times stiffer than Table 1's, the hard case for the implicit solve.
        spec.material.enabled = true;
        spec.material.file = options.material;
        spec.material.material = scene::readMaterialFile(options.material);
        spec.material.thickness = 0.002;
        spec.material.springs.model = SpringModel::Elastic;
        spec.material.springs.initialTemperature = options.temperatureC + 273.15;
        underFlag("--temperature", [&] { validate(spec.material.springs); });
        spec.sheet.lattice.maxCorner.y() = spec.sheet.lattice.minCorner.y() + spec.material.thickness;
    }
    spec.engine = options.engine;
    // The run's own length and rest do not apply: the bench takes its steps.
    spec.run.stopAtRest = false;
    spec.run.duration = std::numeric_limits<Real>::infinity();
    return spec;
}

/// What the timed rounds measured, one entry per round.
struct BenchRounds
{
    std::vector<double> walls; ///< s
    std::vector<double> rates; ///< spring-steps per second
    std::vector<double> baselineRates;
    std::vector<double> ratios; ///< engine over baseline, round by round
    std::uint64_t substeps = 0; ///< in the last round
    long long solverIterations = 0;
    SolverTally solver; ///< the timed steps only: the warm-up step made the first factorisation

    /// s, all the timed rounds together: what the stages' shares of the step are over.
    double timedSeconds() const { return std::accumulate(walls.begin(), walls.end(), 0.0); }
};

/// Repeated rounds, reported by their median: this machine kind shares its host, and single timings wander. The
/// baseline, when asked for, is timed round by round in between, so both see the same load.
BenchRounds timeRounds(Simulator& simulator, Real dt, const BenchOptions& options)
{
    BenchRounds rounds;
    const double springs = double(simulator.system().springCount());
    // A frame's report carries its iterations, residual and cap hits, not its refactorisations: those are counted from
    // the simulator's own tally over the rounds.
    const std::uint64_t refactorisationsBefore = simulator.solverTally().refactorisations;
    for (int round = 0; round < options.repeat; ++round)
    {
        const std::uint64_t substepsBefore = simulator.substepCount();
        const auto start = std::chrono::steady_clock::now();
        for (int i = 0; i < options.steps; ++i)
        {
            const StepReport report = simulator.step(dt);
            rounds.solverIterations += report.solverIterations;
            rounds.solver.add({report.solverIterations, report.solverResidual, report.solverCapHits > 0});
        }
        const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        rounds.substeps = simulator.substepCount() - substepsBefore;
        rounds.walls.push_back(wall);
        rounds.rates.push_back(springs * double(rounds.substeps) / wall);
        if (options.baseline)
        {
            const Real h = dt * double(options.steps) / double(rounds.substeps);
            const double baselineWall = timeScalarBaseline(simulator.system(), h, rounds.substeps);
            rounds.baselineRates.push_back(springs * double(rounds.substeps) / baselineWall);
            rounds.ratios.push_back(rounds.rates.back() / rounds.baselineRates.back());
        }
    }
    rounds.solver.refactorisations = simulator.solverTally().refactorisations - refactorisationsBefore;
    return rounds;
}

/// The share of contact: its own clock against the whole step, and against the spring forces alone, timed on the
/// final state for as many evaluations as the last round made.
nlohmann::json contactFigures(const Simulator& simulator, const ContactSolver& contact, const StageTimer& stageTimer,
                              const BenchRounds& rounds, int repeat)
{
    const double contactSeconds = stageTimer.contactSeconds();
    const double allSeconds = rounds.timedSeconds();
    std::vector<Vec3> force(simulator.system().massCount(), Vec3::Zero());
    const MassSpringSystem& system = simulator.system();
    const PoolScope threads(simulator.pool()); // the spring forces on the threads the steps had
    const auto springStart = std::chrono::steady_clock::now();
    for (std::uint64_t i = 0; i < rounds.substeps; ++i)
    {
        accumulateSpringForces(system.springs, system.forces.repulsion, system.particles.position,
                               system.particles.velocity, force);
    }
    const double springSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - springStart).count() * double(repeat);
    return {
        {"contact_seconds", contactSeconds},
        {"contact_share_of_step", contactSeconds / allSeconds},
        {"spring_force_seconds", springSeconds},
        {"contact_over_spring_forces", contactSeconds / springSeconds},
        {"touching_masses", contact.report().touchingCount()},
        {"detection_seconds", stageTimer.seconds(Stage::ContactDetection)},
        {"projection_seconds", stageTimer.seconds(Stage::ContactProjection)},
        {"sweep_seconds", stageTimer.seconds(Stage::ContactSweep)},
    };
}

/// The bench's JSON line, from the median round (and the best, for the spring rate).
nlohmann::json benchReport(const scene::SceneSpec& spec, const Simulator& simulator, const BenchOptions& options,
                           const BenchRounds& rounds)
{
    std::vector<double> sortedWalls = rounds.walls;
    std::sort(sortedWalls.begin(), sortedWalls.end());
    const double wall = sortedWalls[sortedWalls.size() / 2];
    const double bestWall = sortedWalls.front();
    const double springs = double(simulator.system().springCount());
    const Real dt = spec.time.dt;
    const IntegratorKind kind = spec.time.integrator;
    nlohmann::json out = {
        {"scene", spec.path},
        {"structure", structureName(spec.sheet.lattice.structure)},
        {"size", std::to_string(spec.sheet.lattice.countX) + "x" + std::to_string(spec.sheet.lattice.layers) + "x" +
                     std::to_string(spec.sheet.lattice.countZ)},
        {"integrator", integratorName(kind)},
        {"threads", simulator.threadCount()},
        {"simd", simdPathName(activeSimdPath())},
        {"masses", simulator.system().massCount()},
        {"springs", simulator.system().springCount()},
        {"steps", options.steps},
        {"substeps", rounds.substeps},
        {"dt", dt},
        {"repeat", options.repeat},
        {"wall_seconds", wall},
        {"steps_per_second", double(options.steps) / wall},
        {"spring_steps_per_second", springs * double(rounds.substeps) / wall},
        {"spring_steps_per_second_best", springs * double(rounds.substeps) / bestWall},
        {"realtime_factor", double(options.steps) * dt / wall},
        {"round_wall_seconds", rounds.walls},
    };
    if (options.baseline)
    {
        out["baseline"] = {
            {"what", "plain single-threaded scalar loop: scatter f[a] += f, f[b] -= f, then symplectic Euler"},
            {"spring_steps_per_second", median(rounds.baselineRates)},
            {"speedup", median(rounds.ratios)},
            {"round_speedups", rounds.ratios},
        };
    }
    if (!options.material.empty())
    {
        out["material"] = options.material;
        out["temperature_c"] = options.temperatureC;
    }
    if (!isExplicit(kind))
    {
        out["solver_iterations_per_step"] = double(rounds.solverIterations) / double(options.steps * options.repeat);
        out["solver"] = scene::solverSummary(rounds.solver, simulator.settings().implicit);
    }
    return out;
}

void runBench(const BenchOptions& options)
{
    if (options.steps < 1)
    {
        throw InputError("--steps: must be >= 1 (got " + std::to_string(options.steps) + ")");
    }
    if (options.repeat < 1)
    {
        throw InputError("--repeat: must be >= 1 (got " + std::to_string(options.repeat) + ")");
    }
    const scene::SceneSpec spec = benchScene(options);
    const auto buildStart = std::chrono::steady_clock::now();
    scene::Scene scene(spec);
    Simulator& simulator = scene.simulator();
    const auto warmUpStart = std::chrono::steady_clock::now();
    // A warm-up step, not timed with the rounds: first touch of arrays and, for the implicit integrators, the
    // solver's pattern, its ordering and the Cholesky factor's analysis and first factorisation (seconds at
    // 128x2x128, while a step with that factor takes a fraction of one). It is reported apart, as set-up.
    simulator.step(spec.time.dt);
    const auto warmUpEnd = std::chrono::steady_clock::now();
    StageTimer stageTimer;
    scene.contact().setStageObserver(&stageTimer);
    if (SelfContact* self = scene.selfContact())
    {
        self->setStageObserver(&stageTimer);
    }
    if (EdgeContact* edges = scene.edgeContact())
    {
        edges->setStageObserver(&stageTimer);
    }
    simulator.setStageObserver(&stageTimer);
    const BenchRounds rounds = timeRounds(simulator, spec.time.dt, options);
    nlohmann::json out = benchReport(spec, simulator, options, rounds);
    out["setup_seconds"] = {
        {"scene", std::chrono::duration<double>(warmUpStart - buildStart).count()},
        {"first_step", std::chrono::duration<double>(warmUpEnd - warmUpStart).count()},
    };
    {
        // Where the frame goes: each stage of the frame's table (docs/step.md), the Simulator's own work and its
        // models' hooks in it, as seconds and shares of the timed rounds' wall time (what is left is the caller's
        // loop and the solves' splitting of a frame).
        const double allSeconds = rounds.timedSeconds();
        nlohmann::json stages = nlohmann::json::object();
        for (const StepStageEntry& entry : stepStageTable)
        {
            const double seconds = stageTimer.seconds(entry.stage);
            stages[std::string(entry.name)] = {{"seconds", seconds}, {"share", seconds / allSeconds}};
        }
        out["step_stages"] = stages;
    }
    if (spec.environment.room.enabled || !spec.obstacles.empty())
    {
        out["contact"] = contactFigures(simulator, scene.contact(), stageTimer, rounds, options.repeat);
    }
    if (const SelfContact* self = scene.selfContact())
    {
        // The sheet against itself: its pair lists (Bullet's btDbvt) and its per-substep tests and responses, as
        // shares of the timed rounds' wall time.
        const double allSeconds = rounds.timedSeconds();
        const double pairs = stageTimer.seconds(Stage::SelfContactPairs);
        const double solve = stageTimer.seconds(Stage::SelfContactSolve);
        out["self_contact"] = {
            {"pairs_seconds", pairs},
            {"solve_seconds", solve},
            {"share_of_step", (pairs + solve) / allSeconds},
            {"pair_lists", self->report().queries},
            {"pairs_last_list", self->report().pairs},
            {"touches_last_frame", self->report().lastFrame},
        };
    }
    if (const EdgeContact* edges = scene.edgeContact())
    {
        // The sheet's edges and triangles against the obstacles' edges and corners: its listings (Bullet's btDbvt over
        // the sheet) and its per-substep tests and responses, as shares of the timed rounds' wall time.
        const double allSeconds = rounds.timedSeconds();
        const double pairs = stageTimer.seconds(Stage::EdgeContactPairs);
        const double solve = stageTimer.seconds(Stage::EdgeContactSolve);
        out["edge_contact"] = {
            {"pairs_seconds", pairs},
            {"solve_seconds", solve},
            {"share_of_step", (pairs + solve) / allSeconds},
            {"pair_lists", edges->report().lists},
            {"edge_pairs_last_list", edges->report().edgePairs},
            {"corner_pairs_last_list", edges->report().cornerPairs},
            {"touches_last_frame", edges->report().lastFrame},
        };
    }
    if (!isExplicit(spec.time.integrator))
    {
        // The implicit solve: building each solve's matrix and filter, refreshing (or following) the preconditioner,
        // and the conjugate gradient's iterations, as shares of the timed rounds' wall time; the pattern's analysis is
        // in the untimed warm-up step unless the topology changes.
        const double allSeconds = rounds.timedSeconds();
        const double analysis = stageTimer.seconds(Stage::SolverAnalysis);
        const double assembly = stageTimer.seconds(Stage::SolverAssembly);
        const double preconditioner = stageTimer.seconds(Stage::SolverPreconditioner);
        const double iterations = stageTimer.seconds(Stage::SolverIterations);
        out["solver_stages"] = {
            {"analysis_seconds", analysis},
            {"assembly_seconds", assembly},
            {"preconditioner_seconds", preconditioner},
            {"iterations_seconds", iterations},
            {"share_of_step", (analysis + assembly + preconditioner + iterations) / allSeconds},
            {"assembly_share", assembly / allSeconds},
            {"preconditioner_share", preconditioner / allSeconds},
            {"iterations_share", iterations / allSeconds},
        };
        const std::string warning = scene::solverCapWarning(rounds.solver, simulator.settings().implicit);
        if (!warning.empty())
        {
            std::cerr << warning << std::endl;
        }
    }
    std::cout << out.dump() << std::endl;
}
} // namespace

void addBenchCommand(CLI::App& app)
{
    auto options = std::make_shared<BenchOptions>();
    CLI::App* command = app.add_subcommand(
        "bench", "Time the engine on a scene (by default data/scenes/bench-free-fall.json: a 256x2x256 Table 1 sheet "
                 "falling freely); prints one JSON line");
    command->add_option("scene", options->scene,
                        "Scene file to time (default data/scenes/bench-free-fall.json, or bench-contact.json with "
                        "--contact); its run length and rest are ignored");
    command->add_option("--structure", options->structure, structureNameList() + " (default: the scene's)");
    command->add_option("--size", options->size, "NxLxN (default: the scene's, 256x2x256 in the bench scenes)");
    command->add_option("--integrator", options->integrator, integratorNameList() + " (default: the scene's)");
    command->add_option("--preconditioner", options->preconditioner, "implicit solver: multigrid, cholesky or jacobi");
    command->add_option(
        "--material", options->material,
        "Material file: a 2 mm elastic sheet of it (e.g. data/materials/pet.json) instead of Table 1's");
    command->add_option("--temperature", options->temperatureC, "Temperature of a --material sheet (C)")
        ->capture_default_str();
    command->add_option("--steps", options->steps, "Steps per timed round (after one warm-up step)")
        ->capture_default_str();
    command->add_option("--repeat", options->repeat, "Timed rounds; figures are the median round (and the best)")
        ->capture_default_str();
    command->add_option("--dt", options->dt, "Step in seconds (default: the scene's; explicit integrators substep it)");
    command->add_flag("--contact", options->contact,
                      "Time data/scenes/bench-contact.json (the sheet resting on two boxes) and report the share of "
                      "step time spent on contact");
    addSetOption(*command, options->settings);
    addThreadsOption(*command, options->engine);
    command->add_flag("--baseline", options->baseline,
                      "Also time a plain single-threaded scalar loop over the same springs, round by round, and "
                      "report the engine's speed-up over it (median of the rounds' ratios)");
    command->callback([options] { runBench(*options); });
}
} // namespace masse::app
