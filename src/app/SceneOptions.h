#pragma once
/// Command-line overrides shared by the commands that run scenes (run, paper, view, compare).

#include "scene/SceneOverrides.h"
#include "scene/SceneSpec.h"

#include "core/InputError.h"

#include <string>
#include <vector>

namespace CLI
{
class App;
}

namespace masse::app
{
struct SceneOverrides
{
    std::string integrator;
    std::string dt;       ///< "" when not given; read by applyOverrides, which names the flag of a bad value
    std::string duration; ///< "" when not given
    std::string size;
    std::vector<std::string> settings; ///< --set KEY=VALUE, in the order given
};

/// Adds --integrator, --dt, --duration, --size and --set to a command.
void addSceneOverrides(CLI::App& command, SceneOverrides& overrides);
/// Applies the overrides given (throws InputError for bad values, naming the flag).
void applyOverrides(const SceneOverrides& overrides, scene::SceneSpec& spec);
/// Adds --threads N to a command that simulates. Before the command's action runs, the kernels' thread pool is sized:
/// N if given, else $MASSE_THREADS, else every core (a bad value is an InputError naming the flag or variable).
void addThreadsOption(CLI::App& command);
/// Adds --set KEY=VALUE (repeatable) to a command.
void addSetOption(CLI::App& command, std::vector<std::string>& settings);
/// The --set settings parsed (throws InputError naming a malformed one).
std::vector<scene::KeyOverride> parseSettings(const std::vector<std::string>& settings);
/// Reads the scene at `path` with the --set keys changed, then applies the other overrides.
scene::SceneSpec loadSceneWithOverrides(const std::string& path, const SceneOverrides& overrides);
/// Runs `check`; an InputError about one field of the core's (the value the flag gave) is re-thrown under the flag:
/// "--size: expected NxLxN, e.g. 8x2x8 (got '8x8')". One that names no field already says where it comes from.
template <typename Check> void underFlag(const std::string& flag, Check&& check)
{
    try
    {
        check();
    }
    catch (const InputError& e)
    {
        if (e.field().empty())
        {
            throw;
        }
        throw InputError(flag + ": " + e.problem());
    }
}
/// Where the repository's data folder is (scenes, meshes, materials): $MASSE_DATA or the source tree's data/.
std::string dataDirectory();
} // namespace masse::app
