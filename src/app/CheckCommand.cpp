/// `masse check PATH...`: runs regression scenes and prints a table of what each expected and got.

#include "Commands.h"
#include "SceneOptions.h"

#include "core/InputError.h"
#include "scene/compare/Regression.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <memory>
#include <stdexcept>

namespace masse::app
{
namespace
{
struct CheckOptions
{
    std::vector<std::string> paths;
    bool record = false;
    std::vector<std::string> settings;
    scene::EngineSettings engine;
};

void runCheck(const CheckOptions& options)
{
    std::vector<std::string> files;
    for (const std::string& path : options.paths)
    {
        for (const std::string& file : scene::regressionFiles(path))
        {
            files.push_back(file);
        }
    }
    const std::vector<scene::KeyOverride> overrides = parseSettings(options.settings);
    if (options.record && !overrides.empty())
    {
        throw InputError("--record with --set: the expected results would be recorded for a changed scene");
    }
    if (options.record)
    {
        for (const std::string& file : files)
        {
            scene::recordRegression(file, options.engine);
            std::printf("recorded %s\n", file.c_str());
        }
        return;
    }
    std::vector<scene::RegressionResult> results;
    int failed = 0;
    for (const std::string& file : files)
    {
        results.push_back(scene::runRegression(file, overrides, options.engine));
        failed += results.back().passed() ? 0 : 1;
    }
    std::printf("%s", scene::regressionTable(results).c_str());
    std::printf("\n%zu scene(s): %zu passed, %d failed\n", results.size(), results.size() - std::size_t(failed),
                failed);
    if (failed > 0)
    {
        throw std::runtime_error(std::to_string(failed) + " regression scene(s) failed");
    }
}
} // namespace

void addCheckCommand(CLI::App& app)
{
    auto options = std::make_shared<CheckOptions>();
    CLI::App* command = app.add_subcommand("check", "Run regression scenes and compare with their expected results");
    command->add_option("paths", options->paths, "Scene files or folders (e.g. data/regression)")->required();
    command->add_flag(
        "--record", options->record,
        "Write the observed events and state hash into each file's expect block (after an intended change)");
    addThreadsOption(*command, options->engine);
    addSetOption(*command, options->settings);
    command->callback([options] { runCheck(*options); });
}
} // namespace masse::app
