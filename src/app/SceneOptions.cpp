#include "SceneOptions.h"

#include "core/Format.h"
#include "core/InputError.h"
#include "core/parallel/TaskPool.h"
#include "scene/SceneFile.h"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdlib>
#include <memory>

#ifndef MASSE_DATA_DIR
#define MASSE_DATA_DIR "data"
#endif

namespace masse::app
{
void addSceneOverrides(CLI::App& command, SceneOverrides& overrides)
{
    command.add_option("--integrator", overrides.integrator,
                       "Override: euler, symplectic, verlet, implicit, bdf2 or trbdf2");
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

namespace
{
/// A number of seconds given to `flag`, in (lo, hi] when lo is 0, else in [lo, hi].
double secondsFlag(const std::string& flag, const std::string& text, double lo, double hi)
{
    char* end = nullptr;
    const double value = std::strtod(text.c_str(), &end);
    const std::string range =
        lo == 0 ? "(0, " + formatNumber(hi) + "]" : "[" + formatNumber(lo) + ", " + formatNumber(hi) + "]";
    if (text.empty() || *end != '\0' || !std::isfinite(value) || !(lo == 0 ? value > 0 : value >= lo) || !(value <= hi))
    {
        throw InputError(flag + ": must be a number of seconds in " + range + " (got '" + text + "')");
    }
    return value;
}
} // namespace

void applyOverrides(const SceneOverrides& overrides, scene::SceneSpec& spec)
{
    if (!overrides.integrator.empty())
    {
        underFlag("--integrator", [&] { spec.time.integrator = parseIntegrator(overrides.integrator); });
    }
    if (!overrides.dt.empty())
    {
        spec.time.dt = secondsFlag("--dt", overrides.dt, scene::limits::minTimeStep, scene::limits::maxTimeStep);
    }
    if (!overrides.duration.empty())
    {
        spec.run.duration = secondsFlag("--duration", overrides.duration, 0, scene::limits::maxDuration);
    }
    if (!overrides.dt.empty() || !overrides.duration.empty())
    {
        scene::checkRunLength(spec.time.dt, spec.run.duration, overrides.dt.empty() ? "integrator.dt" : "--dt",
                              overrides.duration.empty() ? "run.duration" : "--duration");
    }
    if (!overrides.size.empty())
    {
        underFlag("--size",
                  [&]
                  {
                      parseSize(overrides.size, spec.sheet.lattice);
                      validate(spec.sheet.lattice);
                  });
        spec.sheet.sizeGiven = "--size"; // the mass indices are checked against it when the scene is built
    }
}

void addThreadsOption(CLI::App& command)
{
    auto threads = std::make_shared<int>(0);
    command.add_option("--threads", *threads,
                       "Threads for the engine's kernels (default: $MASSE_THREADS, else every "
                       "core); results are the same bits at any count");
    command.parse_complete_callback(
        [threads]
        { underFlag("--threads", [&] { setThreadCount(*threads != 0 ? *threads : defaultThreadCount()); }); });
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
