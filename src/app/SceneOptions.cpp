#include "SceneOptions.h"

#include "core/InputError.h"

#include <CLI/CLI.hpp>

#include <cstdlib>

#ifndef MASSE_DATA_DIR
#define MASSE_DATA_DIR "data"
#endif

namespace masse::app
{
void addSceneOverrides(CLI::App& command, SceneOverrides& overrides)
{
    command.add_option("--integrator", overrides.integrator, "Override: euler, symplectic, verlet, implicit or bdf2");
    command.add_option("--dt", overrides.dt, "Override: step in seconds");
    command.add_option("--duration", overrides.duration, "Override: simulated seconds at most");
    command.add_option("--size", overrides.size, "Override: sheet size NxLxN");
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

std::string dataDirectory()
{
    if (const char* data = std::getenv("MASSE_DATA"))
    {
        return data;
    }
    return MASSE_DATA_DIR;
}
} // namespace masse::app
