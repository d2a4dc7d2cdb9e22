#pragma once
/// Reading scene files (JSON) into a SceneSpec. Every key, its unit, default and range: data/scenes/README.md.

#include "scene/SceneSpec.h"

#include <nlohmann/json.hpp>

#include <filesystem>

namespace masse::scene
{
/// Reads and checks a scene file; throws InputError "<file>: <key path>: <what is wrong>" for malformed JSON, an
/// unknown key (with the nearest known key suggested), a wrong type or a value out of range, a script action at a
/// negative time or naming a missing obstacle, grab or mass.
SceneSpec loadScene(const std::string& path);

/// Ranges of the values that, out of them, make a run that never ends or flings the sheet away. Scene keys and flags
/// are held to the same ones.
namespace limits
{
constexpr Real minTimeStep = 1e-6;     ///< s: below it a run of seconds takes more than a million steps
constexpr Real maxTimeStep = 1;        ///< s: the paper's step is 0.03 s
constexpr Real maxDuration = 1e6;      ///< s of simulated time
constexpr Real maxSteps = 1e9;         ///< duration / dt
constexpr Real minMass = 1e-6;         ///< kg per mass (1 mg)
constexpr Real maxMass = 1e3;          ///< kg per mass
constexpr Real maxStiffness = 1e6;     ///< N/m per spring
constexpr Real maxContactRadius = 0.1; ///< m: a mass's sphere, far below the sheet's size
constexpr Real maxRepulsion = 1;       ///< N m^2
} // namespace limits

/// Checks every mass index the scene names (sheet.pinned.masses, a report's such as report.sag.mass, a grab's mass, a
/// script pin's masses) against the sheet it describes now; throws InputError naming the key, e.g. "script[0].mass:
/// 200 is beyond the sheet's 113 masses, 0 to 112 (--size 8x2x8)". Reading the file calls it, and so does building the
/// scene (Scene), after every override (--size, the paper's sizes, the viewer's panel), whatever made the spec.
void checkMassIndices(const SceneSpec& scene);

/// Reads one script action as a scene file's "script" list holds it (the same keys, defaults and checks); `where`
/// names it in messages ("script[2]").
ScriptAction readScriptAction(const nlohmann::json& action, const std::string& where);

/// What a script action may name: the sheet's masses, the obstacles, the grabs before it, the heaters.
struct ScriptTargets
{
    std::size_t masses = 0;
    std::vector<std::string> obstacles;       ///< every obstacle's name, the room's walls included
    std::vector<std::string> staticObstacles; ///< the scene's obstacles without a path, which cannot move
    std::vector<std::string> grabs;           ///< labels of the grabs before the action
    std::vector<std::string> heaters;
    bool heat = false;    ///< the scene has a "heat" section
    bool forming = false; ///< the scene has a "forming" section
};
/// Throws InputError for the action's key (relative to the action: "mass", "grab", "masses.masses", "obstacle",
/// "heater", "action") when the action names something `targets` lacks.
void checkScriptAction(const ScriptAction& action, const ScriptTargets& targets);

/// Throws InputError naming `stepKey` and `durationKey` when duration / dt is more than limits::maxSteps steps.
void checkRunLength(Real dt, Real duration, const std::string& stepKey, const std::string& durationKey);

/// The most files a chain of "extends" may hold (a loop is refused as one, by the files it visits).
constexpr std::size_t maxExtendsDepth = 64;
/// The scene file as JSON, with any "extends" base merged in (RFC 7386 merge patch). A base that does not exist is
/// named with the file that refers to it and its "extends" key; a chain that comes back to one of its files is refused
/// as a loop.
nlohmann::json readSceneDocument(const std::string& path);
/// Makes every key of a scene document that names a file ("material.file", "obstacles[].file") absolute, relative
/// paths taken from `folder`.
void makePathsAbsolute(nlohmann::json& document, const std::filesystem::path& folder);

/// The same from parsed JSON; `baseDirectory` resolves relative mesh paths, `origin` names the source in messages.
SceneSpec parseScene(const nlohmann::json& document, const std::string& baseDirectory, const std::string& origin);
} // namespace masse::scene
