#include "SceneOptions.h"

#include "core/InputError.h"
#include "core/TaskPool.h"

#include <CLI/CLI.hpp>

#include <cstdlib>
#include <memory>

#ifndef MASSE_DATA_DIR
#define MASSE_DATA_DIR "data"
#endif

namespace masse::app
{
void addSceneOverrides(CLI::App& command, SceneOverrides& overrides)
{
    command.add_option("--integrator", overrides.integrator, "Override: euler, symplectic, verlet or implicit");
    command.add_option("--dt", overrides.dt, "Override: step in seconds");
    command.add_option("--duration", overrides.duration, "Override: simulated seconds at most");
    command.add_option("--size", overrides.size, "Override: sheet size NxLxN");
    addSetOption(command, overrides.settings);
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

std::vector<scene::KeyOverride> parseSettings(const std::vector<std::string>& settings)
{
    std::vector<scene::KeyOverride> overrides;
    for (const std::string& setting : settings)
    {
        overrides.push_back(scene::parseKeyOverride(setting));
    }
    return overrides;
}

scene::SceneSpec loadSceneWithOverrides(const std::string& path, const SceneOverrides& overrides)
{
    scene::SceneSpec spec = scene::loadScene(path, parseSettings(overrides.settings));
    applyOverrides(overrides, spec);
    return spec;
}

void applyOverrides(const SceneOverrides& overrides, scene::SceneSpec& spec)
{
    if (!overrides.integrator.empty())
    {
        try
        {
            spec.time.integrator = parseIntegrator(overrides.integrator);
        }
        catch (const InputError& e)
        {
            throw InputError(std::string("--") + e.what());
        }
    }
    if (overrides.dt != 0)
    {
        if (!(overrides.dt > 0))
        {
            throw InputError("--dt: must be > 0 seconds (got " + std::to_string(overrides.dt) + ")");
        }
        spec.time.dt = overrides.dt;
    }
    if (overrides.duration != 0)
    {
        if (!(overrides.duration > 0))
        {
            throw InputError("--duration: must be > 0 seconds (got " + std::to_string(overrides.duration) + ")");
        }
        spec.run.duration = overrides.duration;
    }
    if (!overrides.size.empty())
    {
        try
        {
            parseSize(overrides.size, spec.sheet.lattice);
            validate(spec.sheet.lattice);
        }
        catch (const InputError& e)
        {
            throw InputError(std::string("--") + e.what());
        }
    }
}

void addThreadsOption(CLI::App& command)
{
    auto threads = std::make_shared<int>(0);
    command.add_option("--threads", *threads, "Threads for the engine's kernels (default: $MASSE_THREADS, else every "
                                              "core); results are the same bits at any count");
    command.parse_complete_callback([threads] { setThreadCount(*threads != 0 ? *threads : defaultThreadCount()); });
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
