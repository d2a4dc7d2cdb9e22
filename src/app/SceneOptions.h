#pragma once
/// Command-line overrides shared by the commands that run scenes (run, paper, view, compare).

#include "scene/SceneOverrides.h"
#include "scene/SceneSpec.h"

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
/// Where the repository's data folder is (scenes, meshes, materials): $MASSE_DATA or the source tree's data/.
std::string dataDirectory();
} // namespace masse::app
