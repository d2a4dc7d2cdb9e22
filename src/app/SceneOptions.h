#pragma once
/// Command-line overrides shared by the commands that run scenes (run, paper, view, compare).

#include "scene/SceneOverrides.h"
#include "scene/SceneSpec.h"

#include <string>
#include <vector>

namespace CLI
{
class App;
class Option;
} // namespace CLI

namespace masse::app
{
/// The flags shared by the commands that run scenes; the scene layer applies them (the Python module does the same).
using SceneOverrides = scene::SceneFlags;
using scene::parseSettings;
using scene::underFlag;

/// Adds --integrator, --dt, --duration, --size and --set to a command.
void addSceneOverrides(CLI::App& command, SceneOverrides& overrides);
/// Adds --threads N to a command that simulates. Before the command's action runs, `engine` is filled in: threads N
/// if given, else $MASSE_THREADS, else every core; the stability estimate from $MASSE_STABILITY; and $MASSE_SIMD, if
/// set, forces the SIMD path (a bad value is an InputError naming the flag or variable). This is where the `masse`
/// command reads the engine's environment (scene/EngineEnvironment.h).
void addThreadsOption(CLI::App& command, scene::EngineSettings& engine);
/// Refuses a value of `option` that is not a whole number of threads from 1 to 1024 ("", 0 and 100000 included).
void checkThreadCount(CLI::Option& option);
/// Adds --set KEY=VALUE (repeatable) to a command.
void addSetOption(CLI::App& command, std::vector<std::string>& settings);
/// Reads the scene at `path` with the --set keys changed, then applies the other overrides.
scene::SceneSpec loadSceneWithOverrides(const std::string& path, const SceneOverrides& overrides);
/// Where the repository's data folder is (scenes, meshes, materials): $MASSE_DATA or the source tree's data/.
std::string dataDirectory();
} // namespace masse::app
