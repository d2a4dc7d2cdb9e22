/// `masse bench`: how fast the engine steps a sheet, as one JSON line. "steps" are steps of --dt, each split into
/// "substeps" by the explicit integrators; "spring_steps_per_second" (springs times substeps, divided by wall time)
/// is the figure to compare across sizes, integrators and machines. Each figure is the median of --repeat rounds.

#include "Commands.h"
#include "ScalarBaseline.h"
#include "SceneOptions.h"

#include "bridge/BulletEnvironment.h"

#include "core/ContactSolver.h"
#include "core/Damping.h"
#include "core/Forces.h"
#include "core/Format.h"
#include "core/InputError.h"
#include "core/Lattice.h"
#include "core/MaterialSheet.h"
#include "core/Simulator.h"
#include "core/SimdPath.h"
#include "core/TaskPool.h"
#include "scene/MaterialFile.h"
#include "scene/Runner.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <iostream>
#include <memory>
#include <numeric>
#include <vector>

namespace masse::app
{
namespace
{
struct BenchOptions
{
    std::string structure = "trimm";
    std::string size = "256x2x256";
    std::string integrator = "symplectic";
    int steps = 5;
    int repeat = 5;
    double dt = 0.03; // the paper's step; explicit integrators split it into stable substeps
    bool contact = false;
    bool baseline = false;
    std::string preconditioner = "cholesky";
    std::string material; // a material file: the sheet is made of it (2 mm thick) instead of Table 1's springs
    double temperatureC = 20;
};

double median(std::vector<double> values)
{
    std::sort(values.begin(), values.end());
    return values[values.size() / 2];
}

void runBench(const BenchOptions& options)
{
    LatticeSpec spec;
    spec.structure = parseStructure(options.structure);
    parseSize(options.size, spec);
    const IntegratorKind kind = parseIntegrator(options.integrator);
    if (options.steps < 1)
    {
        throw InputError("--steps: must be >= 1 (got " + std::to_string(options.steps) + ")");
    }
    if (options.repeat < 1)
    {
        throw InputError("--repeat: must be >= 1 (got " + std::to_string(options.repeat) + ")");
    }
    if (!(options.dt > 0))
    {
        throw InputError("--dt: must be > 0 seconds (got " + formatNumber(options.dt) + ")");
    }

    if (options.preconditioner != "cholesky" && options.preconditioner != "jacobi")
    {
        throw InputError("--preconditioner: expected cholesky or jacobi (got '" + options.preconditioner + "')");
    }
    // A material sheet is a real 2 mm sheet (its layer spacing the thickness) at the given temperature: cold, its
    // springs are thousands of times stiffer than Table 1's, the hard case for the implicit solve.
    const Real materialThickness = 0.002;
    if (!options.material.empty())
    {
        spec.maxCorner.y() = spec.minCorner.y() + materialThickness;
    }
    const Lattice lattice = buildLattice(spec);
    MassSpringSystem sheet = options.material.empty()
                                 ? makeSheet(lattice, SheetParams{})
                                 : makeMaterialSheet(lattice, scene::readMaterialFile(options.material),
                                                     materialThickness, options.temperatureC + 273.15);
    sheet.forces.airDamping = airDampingRate(paperAirRetention, paperTimeStep);
    SimulatorSettings settings;
    settings.integrator = kind;
    settings.implicit.preconditioner =
        options.preconditioner == "jacobi" ? PreconditionerKind::Jacobi : PreconditionerKind::Cholesky;
    Simulator simulator(std::move(sheet), settings);

    // With --contact the sheet rests on two boxes (one under each half, a 0.1 m gap between them) in the room.
    bridge::BulletEnvironment environment;
    ContactSettings contactSettings;
    std::unique_ptr<ContactSolver> contact;
    if (options.contact)
    {
        environment.addRoom(bridge::RoomSpec{});
        const Real top = spec.minCorner.y() - contactSettings.radius;
        bridge::ObstacleSpec box;
        box.kind = bridge::ObstacleKind::Box;
        box.halfExtents = Vec3(0.4, 0.5, 0.8);
        box.name = "left";
        box.position = Vec3(-0.1, top - 0.5, 0.3);
        environment.addObstacle(box);
        box.name = "right";
        box.position = Vec3(0.75, top - 0.5, 0.3);
        environment.addObstacle(box);
        contact = std::make_unique<ContactSolver>(environment, contactSettings);
        simulator.setContactSolver(contact.get());
    }

    const Real dt = options.dt;
    simulator.step(dt);
    if (contact)
    {
        contact->timingsReset();
    } // warm-up: first-touch of arrays, the implicit solver's pattern

    // Repeated rounds, reported by their median: this machine kind shares its host, and single timings wander.
    std::vector<double> rates;
    std::vector<double> walls;
    std::vector<double> baselineRates;
    std::vector<double> ratios;
    std::uint64_t substeps = 0;
    long long solverIterations = 0;
    SolverTally timed; // the timed steps only: the warm-up step made the first factorisation
    const double springs = double(simulator.system().springCount());
    for (int round = 0; round < options.repeat; ++round)
    {
        const std::uint64_t substepsBefore = simulator.substepCount();
        const auto start = std::chrono::steady_clock::now();
        for (int i = 0; i < options.steps; ++i)
        {
            const StepReport report = simulator.step(dt);
            solverIterations += report.solverIterations;
            timed.add({report.solverIterations, report.solverResidual, report.solverCapHits > 0});
        }
        const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        substeps = simulator.substepCount() - substepsBefore;
        walls.push_back(wall);
        rates.push_back(springs * double(substeps) / wall);
        if (options.baseline)
        {
            // Interleaved with the engine's rounds, so both see the same load on a shared machine.
            const Real h = dt * double(options.steps) / double(substeps);
            const double baselineWall = timeScalarBaseline(simulator.system(), h, substeps);
            baselineRates.push_back(springs * double(substeps) / baselineWall);
            ratios.push_back(rates.back() / baselineRates.back());
        }
    }
    // The share of contact: its own clock against the whole step, and against the spring forces alone, timed on
    // the final state for as many evaluations as the last round made.
    nlohmann::json contactFigures;
    if (contact)
    {
        const double contactSeconds = contact->timings().total();
        const double allSeconds = std::accumulate(walls.begin(), walls.end(), 0.0);
        std::vector<Vec3> force(simulator.system().massCount(), Vec3::Zero());
        const MassSpringSystem& system = simulator.system();
        const auto springStart = std::chrono::steady_clock::now();
        for (std::uint64_t i = 0; i < substeps; ++i)
        {
            accumulateSpringForces(system.springs, system.forces.repulsion, system.particles.position,
                                   system.particles.velocity, force);
        }
        const double springSeconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - springStart).count() *
            double(options.repeat);
        contactFigures = {
            {"contact_seconds", contactSeconds},
            {"contact_share_of_step", contactSeconds / allSeconds},
            {"spring_force_seconds", springSeconds},
            {"contact_over_spring_forces", contactSeconds / springSeconds},
            {"touching_masses", contact->touchingCount()},
            {"detection_seconds", contact->timings().detection},
            {"projection_seconds", contact->timings().projection},
            {"sweep_seconds", contact->timings().sweep},
        };
    }
    std::vector<double> sortedWalls = walls;
    std::sort(sortedWalls.begin(), sortedWalls.end());
    const double wall = sortedWalls[sortedWalls.size() / 2];
    const double bestWall = sortedWalls.front();

    nlohmann::json out = {
        {"structure", structureName(spec.structure)},
        {"size", options.size},
        {"integrator", integratorName(kind)},
        {"threads", threadCount()},
        {"simd", simdPathName(activeSimdPath())},
        {"masses", simulator.system().massCount()},
        {"springs", simulator.system().springCount()},
        {"steps", options.steps},
        {"substeps", substeps},
        {"dt", dt},
        {"repeat", options.repeat},
        {"wall_seconds", wall},
        {"steps_per_second", double(options.steps) / wall},
        {"spring_steps_per_second", springs * double(substeps) / wall},
        {"spring_steps_per_second_best", springs * double(substeps) / bestWall},
        {"realtime_factor", double(options.steps) * dt / wall},
        {"round_wall_seconds", walls},
    };
    if (contact)
    {
        out["contact"] = contactFigures;
    }
    if (options.baseline)
    {
        out["baseline"] = {
            {"what", "plain single-threaded scalar loop: scatter f[a] += f, f[b] -= f, then symplectic Euler"},
            {"spring_steps_per_second", median(baselineRates)},
            {"speedup", median(ratios)},
            {"round_speedups", ratios},
        };
    }
    if (!options.material.empty())
    {
        out["material"] = options.material;
        out["temperature_c"] = options.temperatureC;
    }
    if (!isExplicit(kind))
    {
        out["solver_iterations_per_step"] = double(solverIterations) / double(options.steps * options.repeat);
        out["solver"] = scene::solverSummary(timed, settings.implicit);
        const std::string warning = scene::solverCapWarning(timed, settings.implicit);
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
    CLI::App* command = app.add_subcommand("bench", "Time the engine on a sheet falling freely; prints one JSON line");
    command->add_option("--structure", options->structure, "square2d, samm, slamm or trimm")->capture_default_str();
    command->add_option("--size", options->size, "NxLxN")->capture_default_str();
    command->add_option("--integrator", options->integrator, "euler, symplectic, verlet, implicit or bdf2")
        ->capture_default_str();
    command->add_option("--preconditioner", options->preconditioner, "implicit solver: cholesky or jacobi")
        ->capture_default_str();
    command->add_option("--material", options->material,
                        "Material file: a 2 mm sheet of it (e.g. data/materials/pet.json) instead of Table 1's");
    command->add_option("--temperature", options->temperatureC, "Temperature of a --material sheet (C)")
        ->capture_default_str();
    command->add_option("--steps", options->steps, "Steps per timed round (after one warm-up step)")
        ->capture_default_str();
    command->add_option("--repeat", options->repeat, "Timed rounds; figures are the median round (and the best)")
        ->capture_default_str();
    command->add_option("--dt", options->dt, "Step in seconds (explicit integrators substep it)")
        ->capture_default_str();
    command->add_flag("--contact", options->contact,
                      "Rest the sheet on two boxes and report the share of step time spent on contact");
    addThreadsOption(*command);
    command->add_flag("--baseline", options->baseline,
                      "Also time a plain single-threaded scalar loop over the same springs, round by round, and "
                      "report the engine's speed-up over it (median of the rounds' ratios)");
    command->callback([options] { runBench(*options); });
}
} // namespace masse::app
