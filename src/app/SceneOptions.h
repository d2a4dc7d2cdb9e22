#pragma once
/// Command-line overrides shared by the commands that run scenes (run, paper, view, compare).

#include "scene/SceneSpec.h"

#include <string>

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
};

/// Adds --integrator, --dt, --duration and --size to a command.
void addSceneOverrides(CLI::App& command, SceneOverrides& overrides);
/// Applies the overrides given (throws InputError for bad values, naming the flag).
void applyOverrides(const SceneOverrides& overrides, scene::SceneSpec& spec);
/// Where the repository's data folder is (scenes, meshes, materials): $MASSE_DATA or the source tree's data/.
std::string dataDirectory();
} // namespace masse::app
