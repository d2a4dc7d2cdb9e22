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
    double dt = 0;
    double duration = 0;
    std::string size;
};

/// Adds --integrator, --dt, --duration and --size to a command.
void addSceneOverrides(CLI::App& command, SceneOverrides& overrides);
/// Applies the overrides given (throws InputError for bad values, naming the flag).
void applyOverrides(const SceneOverrides& overrides, scene::SceneSpec& spec);
/// Adds --threads N to a command that simulates. Before the command's action runs, the kernels' thread pool is sized:
/// N if given, else $MASSE_THREADS, else every core (a bad value is an InputError naming the flag or variable).
void addThreadsOption(CLI::App& command);
/// Where the repository's data folder is (scenes, meshes, materials): $MASSE_DATA or the source tree's data/.
std::string dataDirectory();
} // namespace masse::app
