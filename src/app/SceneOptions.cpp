#include "SceneOptions.h"

#include "scene/EngineEnvironment.h"

#include "core/parallel/TaskPool.h"

#include <CLI/CLI.hpp>

#include <cerrno>
#include <cstdlib>
#include <memory>

#ifndef MASSE_DATA_DIR
#define MASSE_DATA_DIR "data"
#endif

namespace masse::app
{
namespace
{
/// An empty value (`--dt ''`, most often a shell variable that was never set) is a mistake, not "not given": the
/// overrides keep "" for a flag that was not given, and would run the scene's own value silently.
const CLI::Validator nonEmpty([](std::string& value) { return value.empty() ? "needs a value (got '')" : ""; }, "",
                              "NONEMPTY");

/// A thread count as a whole number in [1, 1024]; "" and 0 are refused like any other value outside it.
const CLI::Validator threadCount(
    [](std::string& value)
    {
        errno = 0;
        char* end = nullptr;
        const long threads = std::strtol(value.c_str(), &end, 10);
        if (value.empty() || *end != '\0' || errno != 0 || threads < 1 || threads > 1024)
        {
            return "must be a whole number of threads from 1 to 1024 (got '" + value + "')";
        }
        return std::string();
    },
    "", "THREADS");
} // namespace

void addSceneOverrides(CLI::App& command, SceneOverrides& overrides)
{
    command.add_option("--integrator", overrides.integrator, "Override: " + integratorNameList())->check(nonEmpty);
    command.add_option("--dt", overrides.dt, "Override: step in seconds")->check(nonEmpty);
    command.add_option("--duration", overrides.duration, "Override: simulated seconds at most")->check(nonEmpty);
    command.add_option("--size", overrides.size, "Override: sheet size NxLxN")->check(nonEmpty);
    addSetOption(command, overrides.settings);
}

void checkThreadCount(CLI::Option& option)
{
    option.check(threadCount);
}

void addSetOption(CLI::App& command, std::vector<std::string>& settings)
{
    command
        .add_option("--set", settings,
                    "Set a scene key by its path, KEY=VALUE (JSON or plain text), e.g. heat.heaters[0].power=8000; "
                    "repeatable")
        ->take_all()
        ->allow_extra_args(false);
}

scene::SceneSpec loadSceneWithOverrides(const std::string& path, const SceneOverrides& overrides)
{
    return scene::loadScene(path, overrides);
}

void addThreadsOption(CLI::App& command, scene::EngineSettings& engine)
{
    auto threads = std::make_shared<int>(0);
    command
        .add_option("--threads", *threads,
                    "Threads for the engine's kernels (default: $MASSE_THREADS, else every "
                    "core); results are the same bits at any count")
        ->check(threadCount);
    command.parse_complete_callback(
        [threads, &engine]
        {
            if (*threads != 0)
            {
                underFlag("--threads", [&] { requireThreadCount(*threads); });
            }
            engine = scene::engineFromEnvironment(*threads);
            // Started once here and stopped: a count the system cannot start (a memory or process limit) is refused
            // naming the flag, before any scene is read or folder touched. Each scene then starts a pool of its own.
            underFlag("--threads", [&] { const TaskPool probe(engine.threads); });
            scene::applySimdFromEnvironment();
        });
}

std::string dataDirectory()
{
    if (const char* data = std::getenv("MASSE_DATA"))
    {
        return data;
    }
    return MASSE_DATA_DIR;
}
} // namespace masse::app
