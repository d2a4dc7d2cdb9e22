#include "scene/SceneOverrides.h"

#include "scene/SceneFile.h"

#include "core/Format.h"
#include "core/InputError.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>

namespace masse::scene
{
namespace
{
/// True if `message` ("<origin>: <key path>: ...") is about `key` or something inside it.
bool isAbout(const std::string& message, const std::string& origin, const std::string& key)
{
    const std::string head = origin + ": " + key;
    if (message.compare(0, head.size(), head) != 0 || message.size() == head.size())
    {
        return false;
    }
    const char next = message[head.size()];
    return next == ':' || next == '.' || next == '[';
}

/// Whether the document reads as a scene without any setting.
bool readsWithout(const nlohmann::json& document, const std::string& baseDirectory, const std::string& origin)
{
    try
    {
        parseScene(document, baseDirectory, origin);
        return true;
    }
    catch (const InputError&)
    {
        return false;
    }
}

void rebase(nlohmann::json& holder, const std::filesystem::path& from, const std::filesystem::path& to)
{
    if (!holder.is_object() || !holder.contains("file") || !holder["file"].is_string())
    {
        return;
    }
    const std::filesystem::path file = holder["file"].get<std::string>();
    if (file.is_relative())
    {
        holder["file"] = std::filesystem::relative(std::filesystem::absolute(from / file).lexically_normal(),
                                                   std::filesystem::absolute(to))
                             .string();
    }
}
} // namespace

KeyOverride parseKeyOverride(const std::string& setting)
{
    const std::size_t equals = setting.find('=');
    if (equals == std::string::npos)
    {
        throw InputError("--set " + setting + ": expected KEY=VALUE, such as heat.heaters[0].power=8000");
    }
    KeyOverride override;
    override.text = setting;
    try
    {
        override.key = parseJsonPath(setting.substr(0, equals));
    }
    catch (const InputError& e)
    {
        throw InputError("--set " + setting + ": " + e.what());
    }
    const std::string value = setting.substr(equals + 1);
    // JSON when it parses as JSON, otherwise the text itself: "implicit" and "12x2x12" need no quotes.
    override.value = nlohmann::json::parse(value, nullptr, false);
    if (override.value.is_discarded())
    {
        override.value = value;
    }
    return override;
}

void applyKeyOverrides(nlohmann::json& document, const std::vector<KeyOverride>& overrides, const std::string& prefix)
{
    for (const KeyOverride& o : overrides)
    {
        try
        {
            assignAt(document, o.key, o.value);
        }
        catch (const InputError& e)
        {
            throw InputError(prefix + o.text + ": " + e.what());
        }
    }
}

SceneSpec parseSceneWith(const nlohmann::json& document, const std::vector<KeyOverride>& overrides,
                         const std::string& baseDirectory, const std::string& origin, const std::string& prefix)
{
    nlohmann::json changed = document;
    applyKeyOverrides(changed, overrides, prefix);
    try
    {
        return parseScene(changed, baseDirectory, origin);
    }
    catch (const InputError& e)
    {
        for (const KeyOverride& o : overrides)
        {
            if (isAbout(e.what(), origin, o.key.text()))
            {
                throw InputError(prefix + o.text + ": " + e.what());
            }
        }
        // An error about another key (the pins of a sheet made smaller, an integrator that edge contact refuses):
        // when the file reads without the settings, the settings caused it, and the message names them.
        if (!overrides.empty() && readsWithout(document, baseDirectory, origin))
        {
            std::string settings;
            for (const KeyOverride& o : overrides)
            {
                settings += (settings.empty() ? "" : ", ") + prefix + o.text;
            }
            throw InputError(settings + ": " + e.what());
        }
        throw;
    }
}

SceneSpec loadScene(const std::string& path, const std::vector<KeyOverride>& overrides)
{
    if (overrides.empty())
    {
        return loadScene(path);
    }
    return parseSceneWith(readSceneDocument(path), overrides, std::filesystem::path(path).parent_path().string(), path);
}

std::vector<KeyOverride> parseSettings(const std::vector<std::string>& settings)
{
    std::vector<KeyOverride> overrides;
    for (const std::string& setting : settings)
    {
        overrides.push_back(parseKeyOverride(setting));
    }
    return overrides;
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

void applyFlags(const SceneFlags& flags, SceneSpec& spec)
{
    spec.engine = flags.engine;
    if (!flags.integrator.empty())
    {
        underFlag("--integrator", [&] { spec.time.integrator = parseIntegrator(flags.integrator); });
    }
    if (!flags.dt.empty())
    {
        spec.time.dt = secondsFlag("--dt", flags.dt, limits::minTimeStep, limits::maxTimeStep);
    }
    if (!flags.duration.empty())
    {
        spec.run.duration = secondsFlag("--duration", flags.duration, 0, limits::maxDuration);
    }
    if (!flags.dt.empty() || !flags.duration.empty())
    {
        checkRunLength(spec.time.dt, spec.run.duration, flags.dt.empty() ? "integrator.dt" : "--dt",
                       flags.duration.empty() ? "run.duration" : "--duration");
    }
    if (!flags.size.empty())
    {
        underFlag("--size",
                  [&]
                  {
                      parseSize(flags.size, spec.sheet.lattice);
                      validate(spec.sheet.lattice);
                  });
        spec.sheet.sizeGiven = "--size"; // the mass indices are checked against it when the scene is built
    }
}

SceneSpec loadScene(const std::string& path, const SceneFlags& flags)
{
    SceneSpec spec = loadScene(path, parseSettings(flags.settings));
    applyFlags(flags, spec);
    return spec;
}

SceneSpec parseSceneWith(const nlohmann::json& document, const SceneFlags& flags, const std::string& baseDirectory,
                         const std::string& origin)
{
    SceneSpec spec = parseSceneWith(document, parseSettings(flags.settings), baseDirectory, origin);
    applyFlags(flags, spec);
    return spec;
}

void rebaseFilePaths(nlohmann::json& document, const std::string& fromDirectory, const std::string& toDirectory)
{
    if (!document.is_object())
    {
        return;
    }
    const std::filesystem::path from = fromDirectory.empty() ? "." : fromDirectory;
    const std::filesystem::path to = toDirectory.empty() ? "." : toDirectory;
    if (document.contains("material"))
    {
        rebase(document["material"], from, to);
    }
    if (document.contains("obstacles") && document["obstacles"].is_array())
    {
        for (nlohmann::json& obstacle : document["obstacles"])
        {
            rebase(obstacle, from, to);
        }
    }
}
} // namespace masse::scene
