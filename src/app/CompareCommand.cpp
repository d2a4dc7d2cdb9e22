/// `masse compare SCENE --out DIR`: MaSSE and its Bullet soft-body twin side by side on one scene; writes
/// compare.json, series.csv and three plots, and prints a side-by-side table and the twin's approximations.

#include "Commands.h"
#include "SceneOptions.h"

#include "core/InputError.h"
#include "scene/SceneFile.h"
#include "scene/compare/Comparison.h"
#include "scene/output/OutputFolder.h"
#include "scene/output/Progress.h"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <unistd.h>

namespace masse::app
{
namespace
{
struct CompareCommandOptions
{
    std::string scene;
    std::string out;
    std::vector<int> bulletIterations;
    int bulletSubsteps = 0;
    bool quiet = false;
    bool force = false;
    SceneOverrides overrides;
};

void runCompare(const CompareCommandOptions& options, bool substepsGiven)
{
    // Everything that can be wrong with the input is found before the output folder is touched: the scene, the
    // flags, and what the twin refuses (it is built, and calibrated if asked, here).
    scene::SceneSpec spec = loadSceneWithOverrides(options.scene, options.overrides);
    scene::CompareOptions compare;
    compare.bulletIterations = options.bulletIterations;
    if (substepsGiven && options.bulletSubsteps < 1)
    {
        throw InputError("--bullet-substeps: must be a whole number in [1, 10000] (got " +
                         std::to_string(options.bulletSubsteps) + ")");
    }
    compare.bulletSubsteps = options.bulletSubsteps;
    scene::validate(compare);
    scene::OutputFolder folder(options.out, options.force);
    const bool quiet = options.quiet;
    scene::Comparison comparison(std::move(spec), compare,
                                 [quiet](const std::string& line)
                                 {
                                     if (!quiet)
                                     {
                                         std::cerr << line << std::endl;
                                     }
                                 });

    // As `masse run` does: a step the explicit integrators cut into more than a thousand substeps is said up front.
    if (const std::string warning = comparison.scene().substepWarning(); !warning.empty())
    {
        std::cerr << "warning: " << warning << "\n";
    }
    const auto start = std::chrono::steady_clock::now();
    scene::Progress progress(std::cerr, ::isatty(STDERR_FILENO) != 0, comparison.scene().spec().run.duration);
    comparison.run(
        [&](Real simTime, const std::string& latest)
        {
            if (!quiet)
            {
                progress.update(simTime, std::chrono::duration<Real>(std::chrono::steady_clock::now() - start).count(),
                                latest);
            }
        });
    if (!quiet)
    {
        progress.finish(comparison.time(),
                        std::chrono::duration<Real>(std::chrono::steady_clock::now() - start).count());
    }
    comparison.writeOutputs(folder.staging());
    folder.commit();

    std::printf("%s\n", comparison.table().c_str());
    std::printf("Approximations (how the Bullet twin differs from the scene):\n");
    for (const scene::Approximation& a : comparison.approximations())
    {
        const std::size_t bulletRuns = comparison.results().size() - 1;
        std::string runs;
        if (a.runs.size() < bulletRuns)
        {
            for (const std::string& run : a.runs)
            {
                runs += (runs.empty() ? " [" : ", ") + run;
            }
            runs += "]";
        }
        std::printf("- %s%s: %s\n", a.subject.c_str(), runs.c_str(), a.message.c_str());
    }
    std::printf("\nwrote %s/compare.json, series.csv, penetration.png, kinetic_energy.png, distance.png\n",
                options.out.c_str());
}
} // namespace

void addCompareCommand(CLI::App& app)
{
    auto options = std::make_shared<CompareCommandOptions>();
    CLI::App* command = app.add_subcommand(
        "compare", "Run a scene in MaSSE and in its Bullet soft-body twin side by side; write compare.json and plots");
    command->add_option("scene", options->scene, "Scene file (JSON)")->required();
    command->add_option("--out", options->out, "Output folder (created if missing)")->required();
    command->add_flag("--force", options->force, "Replace an --out folder that already holds files");
    command
        ->add_option("--bullet-iterations", options->bulletIterations,
                     "One Bullet run per count of position-solver passes, e.g. 1,2,4,10 (default: the scene's "
                     "bullet.piterations)")
        ->delimiter(',');
    CLI::Option* substeps =
        command->add_option("--bullet-substeps", options->bulletSubsteps,
                            "Bullet substeps per scene step (default: the scene's bullet.substeps)");
    command->add_flag("--quiet", options->quiet, "No progress display");
    addThreadsOption(*command, options->overrides.engine);
    addSceneOverrides(*command, options->overrides);
    command->callback([options, substeps] { runCompare(*options, substeps->count() > 0); });
}
} // namespace masse::app
