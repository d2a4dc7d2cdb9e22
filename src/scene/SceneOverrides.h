#pragma once
/// `--set KEY=VALUE`: changes to a scene's keys from the command line or a study, applied to the scene document
/// (after any "extends" is merged) before it is read, so a key set this way is checked like one in the file.

#include "scene/SceneFile.h"
#include "scene/SceneSpec.h"
#include "scene/json/JsonPath.h"

#include "core/InputError.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace masse::scene
{
struct KeyOverride
{
    JsonPath key;
    nlohmann::json value;
    /// As given ("heat.heaters[0].power=8000"), for messages.
    std::string text;
};

/// Parses "KEY=VALUE": the value as JSON (8000, true, [0, 1, 0], "text"), or as a plain string when it is not JSON
/// (implicit, 12x2x12). Throws InputError "--set <text>: ..." when there is no '=' or the key is malformed.
KeyOverride parseKeyOverride(const std::string& setting);

/// Sets each key in the document, in order. Throws InputError "<prefix><key>: ..." when a key's path cannot be
/// followed (an index past the end of a list, a key inside a number).
void applyKeyOverrides(nlohmann::json& document, const std::vector<KeyOverride>& overrides,
                       const std::string& prefix = "--set ");

/// Reads the scene with the keys set; an error about a key that was set (an unknown key, a value out of range) is
/// reported as "--set <KEY=VALUE>: <file>: <key>: <what is wrong>".
SceneSpec loadScene(const std::string& path, const std::vector<KeyOverride>& overrides);

/// The same as parseScene, with errors about a set key attributed to the setting as above ("<prefix><text>: ...").
SceneSpec parseSceneWith(const nlohmann::json& document, const std::vector<KeyOverride>& overrides,
                         const std::string& baseDirectory, const std::string& origin,
                         const std::string& prefix = "--set ");

/// What the commands that run scenes (run, view, compare, paper) and the Python module take besides the scene: the
/// values of --integrator, --dt, --duration and --size as given ("" when not), the --set settings as text, and the
/// engine settings (from --threads and the environment).
struct SceneFlags
{
    std::string integrator;
    std::string dt; ///< read by applyFlags, which names the flag of a bad value
    std::string duration;
    std::string size;
    std::vector<std::string> settings; ///< KEY=VALUE, in the order given
    EngineSettings engine;
};

/// The --set settings parsed (throws InputError naming a malformed one).
std::vector<KeyOverride> parseSettings(const std::vector<std::string>& settings);
/// Applies the flags other than --set, and the engine settings (throws InputError for bad values, naming the flag).
void applyFlags(const SceneFlags& flags, SceneSpec& spec);
/// Reads the scene at `path` with the --set keys changed, then applies the other flags.
SceneSpec loadScene(const std::string& path, const SceneFlags& flags);
/// The same from a scene document (see parseSceneWith).
SceneSpec parseSceneWith(const nlohmann::json& document, const SceneFlags& flags, const std::string& baseDirectory,
                         const std::string& origin);

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

/// Makes a scene document's relative file paths (material file, mesh obstacles), written relative to `fromDirectory`,
/// relative to `toDirectory` instead, so the document can be saved there.
void rebaseFilePaths(nlohmann::json& document, const std::string& fromDirectory, const std::string& toDirectory);
} // namespace masse::scene
