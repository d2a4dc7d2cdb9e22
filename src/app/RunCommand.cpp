/// `masse run SCENE --out DIR`: runs a scene headless and writes summary.json, events.csv and frames.

#include "Commands.h"
#include "SceneOptions.h"

#include "core/InputError.h"
#include "scene/Runner.h"
#include "scene/SceneFile.h"
#include "scene/output/OutputFolder.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <unistd.h>

namespace masse::app
{
namespace
{
constexpr int notGiven = std::numeric_limits<int>::min();

struct RunOptions
{
    std::string scene;
    std::string out;
    int framesEvery = notGiven;
    std::vector<std::string> formats;
    bool quiet = false;
    bool force = false;
    SceneOverrides overrides;
};

void runRun(const RunOptions& options)
{
    // Everything that can be wrong with the input is found before the output folder is touched.
    scene::SceneSpec spec = loadSceneWithOverrides(options.scene, options.overrides);
    scene::applyFrameFlags(spec,
                           options.framesEvery != notGiven ? std::optional<int>(options.framesEvery) : std::nullopt,
                           options.formats);
    // The run writes into a staging folder that replaces --out only when it has finished: never half a run, never
    // an earlier run's files beside this one's.
    scene::OutputFolder folder(options.out, options.force);
    scene::Scene scene(spec);

    scene::RunOptions run;
    run.outDir = folder.staging();
    run.showProgress = !options.quiet;
    run.terminal = ::isatty(STDERR_FILENO) != 0;
    const scene::RunResult result = scene::runScene(scene, run, std::cerr);
    folder.commit();

    const nlohmann::json& s = result.summary;
    std::printf("scene %s: %s %s, %zu masses, %zu springs, %s dt = %g s\n", s["scene"].get<std::string>().c_str(),
                s["structure"].get<std::string>().c_str(), s["size"].get<std::string>().c_str(),
                s["masses"].get<std::size_t>(), s["springs"].get<std::size_t>(),
                s["integrator"].get<std::string>().c_str(), s["dt"].get<double>());
    std::printf("%-10s %-14s %10s %10s\n", "event", "object", "sim s", "wall s");
    for (const auto& e : s["events"])
    {
        std::printf("%-10s %-14s %10.3f %10.3f\n", e["name"].get<std::string>().c_str(),
                    e["object"].get<std::string>().c_str(), e["sim_time"].get<double>(), e["wall_time"].get<double>());
    }
    std::printf(
        "simulated %.2f s in %.2f s wall (%.2fx real time); final kinetic energy %.3g J, max penetration %.3g m, "
        "state %s\n",
        s["sim_seconds"].get<double>(), s["wall_seconds"].get<double>(), s["realtime_factor"].get<double>(),
        s["final"]["kinetic_energy"].get<double>(), s["final"]["max_penetration"].get<double>(),
        s["final"]["state_hash"].get<std::string>().c_str());
    if (s.contains("solver"))
    {
        const nlohmann::json& solver = s["solver"];
        std::printf("implicit solver (%s): %.2f iterations a step (largest %d), %llu steps at the cap of %d, final "
                    "residual %.3g, %llu refactorisations\n",
                    solver["preconditioner"].get<std::string>().c_str(), solver["mean_iterations"].get<double>(),
                    solver["largest_iterations"].get<int>(),
                    static_cast<unsigned long long>(solver["steps_at_iteration_cap"].get<std::uint64_t>()),
                    solver["max_iterations"].get<int>(), solver["final_residual"].get<double>(),
                    static_cast<unsigned long long>(solver["refactorisations"].get<std::uint64_t>()));
        const std::string warning = scene::solverCapWarning(scene.simulator().solverTally(), spec.time.implicit);
        if (!warning.empty())
        {
            std::fprintf(stderr, "%s\n", warning.c_str());
        }
    }
    if (s.contains("webbing"))
    {
        // Where the sheet lies on itself: the defect a forming engineer looks for first.
        const nlohmann::json& webbing = s["webbing"];
        std::printf("webbing: %zu place(s), %zu masses within %.3g m of another part of the sheet%s\n",
                    webbing["places"].get<std::size_t>(), webbing["masses"].get<std::size_t>(),
                    webbing["distance_m"].get<double>(), options.out.empty() ? "" : " (webbing.csv)");
    }
    if (!options.out.empty())
    {
        std::printf("wrote %s/summary.json and events.csv\n", options.out.c_str());
    }
}
} // namespace

void addRunCommand(CLI::App& app)
{
    auto options = std::make_shared<RunOptions>();
    CLI::App* command = app.add_subcommand("run", "Run a scene headless; write summary.json, events.csv and frames");
    command->add_option("scene", options->scene, "Scene file (JSON)")->required();
    command->add_option("--out", options->out,
                        "Output folder (created if missing; written when the run has finished, never half)");
    command->add_flag("--force", options->force, "Replace an --out folder that already holds files");
    command->add_option("--frames-every", options->framesEvery, "Write the sheet every K steps (0: never)");
    command->add_option("--format", options->formats, "Frame formats: vtp, obj")->delimiter(',');
    command->add_flag("--quiet", options->quiet, "No progress display");
    addThreadsOption(*command, options->overrides.engine);
    addSceneOverrides(*command, options->overrides);
    command->callback([options] { runRun(*options); });
}
} // namespace masse::app
