#include "scene/json/JsonObject.h"
#include "core/Format.h"

#include "core/InputError.h"
#include "core/NearestName.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

namespace masse::scene
{
namespace
{
std::string describe(const nlohmann::json& value)
{
    std::string text = value.dump();
    return text.size() > 40 ? text.substr(0, 37) + "..." : text;
}

} // namespace

std::size_t editDistance(const std::string& a, const std::string& b)
{
    return masse::editDistance(a, b);
}

namespace
{
/// Follows the parser through the document so that an error can name the key it was reading ("sheet.mass"), and
/// refuses nesting deeper than any scene needs before it can exhaust the stack (dump, compare and copy recurse).
class KeyTracker
{
public:
    bool operator()(int /*depth*/, nlohmann::json::parse_event_t event, nlohmann::json& parsed)
    {
        using Event = nlohmann::json::parse_event_t;
        switch (event)
        {
        case Event::object_start:
        case Event::array_start:
            if (m_frames.size() >= maxJsonDepth)
            {
                throw InputError(where() + ": nested deeper than " + std::to_string(maxJsonDepth) + " levels");
            }
            m_frames.push_back({event == Event::array_start, "", 0});
            break;
        case Event::key:
            m_frames.back().key = parsed.get<std::string>();
            break;
        case Event::object_end:
        case Event::array_end:
            m_frames.pop_back();
            advance();
            break;
        case Event::value:
            advance();
            break;
        }
        return true;
    }

    /// The path of the value being read: "sheet.pinned.masses[2]", or "the top level".
    std::string where() const
    {
        std::string path;
        for (const Frame& frame : m_frames)
        {
            if (frame.array)
            {
                path += "[" + std::to_string(frame.index) + "]";
            }
            else if (!frame.key.empty())
            {
                path += (path.empty() ? "" : ".") + frame.key;
            }
        }
        return path.empty() ? "the top level" : path;
    }

private:
    struct Frame
    {
        bool array;
        std::string key;
        std::size_t index;
    };

    void advance()
    {
        if (!m_frames.empty() && m_frames.back().array)
        {
            ++m_frames.back().index;
        }
    }

    std::vector<Frame> m_frames;
};

/// The part of nlohmann's message after its "[json.exception...]" tag.
std::string plainMessage(const std::string& message, const std::string& from)
{
    const std::size_t at = message.find(from);
    if (at == std::string::npos)
    {
        return message;
    }
    return from == "] " ? message.substr(at + 2) : message.substr(at);
}
} // namespace

nlohmann::json readJsonFile(const std::string& path)
{
    std::error_code error;
    const std::filesystem::file_status status = std::filesystem::status(path, error);
    if (std::filesystem::is_directory(status))
    {
        throw InputError(path + ": is a folder, not a JSON file");
    }
    if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status))
    {
        // A device or a pipe ("extends": "/dev/stdin") could be read for ever.
        throw InputError(path + ": is not a regular file");
    }
    std::ifstream in(path);
    if (!in)
    {
        throw InputError(path + ": cannot be read (does the file exist?)");
    }
    KeyTracker tracker;
    try
    {
        // Comments allowed; the callback keeps every value and only watches.
        return nlohmann::json::parse(in, std::ref(tracker), true, true);
    }
    catch (const nlohmann::json::parse_error& e)
    {
        // nlohmann's message names the line and column ("[json.exception.parse_error.101] parse error at line 3...").
        throw InputError(path + ": malformed JSON: " + plainMessage(e.what(), "parse error"));
    }
    catch (const nlohmann::json::out_of_range& e)
    {
        // A number beyond double range ("1e400"): name the key it was given for.
        throw InputError(path + ": " + tracker.where() + ": " + plainMessage(e.what(), "number overflow") +
                         " (beyond the range of double precision)");
    }
    catch (const nlohmann::json::exception& e)
    {
        throw InputError(path + ": " + tracker.where() + ": " + plainMessage(e.what(), "] "));
    }
    catch (const InputError& e)
    {
        throw InputError(path + ": " + e.what());
    }
}

JsonObject::JsonObject(const nlohmann::json& value, std::string path) : m_value(value), m_path(std::move(path))
{
    if (!m_value.is_object())
    {
        throw InputError((m_path.empty() ? std::string("the file") : m_path) + ": expected an object {...} (got " +
                         describe(m_value) + ")");
    }
}

std::string JsonObject::pathOf(const std::string& key) const
{
    return m_path.empty() ? key : m_path + "." + key;
}

void JsonObject::fail(const std::string& key, const std::string& message) const
{
    throw InputError(pathOf(key) + ": " + message);
}

const nlohmann::json* JsonObject::find(const std::string& key) const
{
    if (std::find(m_known.begin(), m_known.end(), key) == m_known.end())
    {
        m_known.push_back(key);
    }
    const auto it = m_value.find(key);
    return it == m_value.end() ? nullptr : &*it;
}

const nlohmann::json& JsonObject::require(const std::string& key) const
{
    const nlohmann::json* value = find(key);
    if (!value)
    {
        fail(key, "is required");
    }
    return *value;
}

bool JsonObject::has(const std::string& key) const
{
    return find(key) != nullptr;
}

const nlohmann::json* JsonObject::raw(const std::string& key) const
{
    return find(key);
}

Real JsonObject::number(const std::string& key) const
{
    const nlohmann::json& value = require(key);
    if (!value.is_number())
    {
        fail(key, "expected a number (got " + describe(value) + ")");
    }
    const Real number = value.get<Real>();
    if (!std::isfinite(number))
    {
        fail(key, "expected a finite number");
    }
    return number;
}

Real JsonObject::number(const std::string& key, Real fallback, Real min, Real max) const
{
    if (!find(key))
    {
        return fallback;
    }
    const Real value = number(key);
    if (value < min || value > max)
    {
        const std::string range = std::isinf(max)   ? ">= " + formatNumber(min)
                                  : std::isinf(min) ? "<= " + formatNumber(max)
                                                    : "in [" + formatNumber(min) + ", " + formatNumber(max) + "]";
        fail(key, "must be " + range + " (got " + formatNumber(value) + ")");
    }
    return value;
}

Real JsonObject::positive(const std::string& key, Real fallback) const
{
    if (!find(key))
    {
        return fallback;
    }
    const Real value = number(key);
    if (!(value > 0))
    {
        fail(key, "must be > 0 (got " + formatNumber(value) + ")");
    }
    return value;
}

int JsonObject::integer(const std::string& key, int fallback, int min, int max) const
{
    const nlohmann::json* value = find(key);
    if (!value)
    {
        return fallback;
    }
    if (!value->is_number_integer())
    {
        fail(key, "expected a whole number (got " + describe(*value) + ")");
    }
    const long long number = value->get<long long>();
    if (number < min || number > max)
    {
        fail(key, "must be in [" + std::to_string(min) + ", " + std::to_string(max) + "] (got " +
                      std::to_string(number) + ")");
    }
    return int(number);
}

bool JsonObject::boolean(const std::string& key, bool fallback) const
{
    const nlohmann::json* value = find(key);
    if (!value)
    {
        return fallback;
    }
    if (!value->is_boolean())
    {
        fail(key, "expected true or false (got " + describe(*value) + ")");
    }
    return value->get<bool>();
}

std::string JsonObject::string(const std::string& key) const
{
    const nlohmann::json& value = require(key);
    if (!value.is_string())
    {
        fail(key, "expected a string (got " + describe(value) + ")");
    }
    return value.get<std::string>();
}

std::string JsonObject::string(const std::string& key, const std::string& fallback) const
{
    return find(key) ? string(key) : fallback;
}

std::string JsonObject::choice(const std::string& key, const std::string& fallback,
                               const std::vector<std::string>& choices) const
{
    const std::string value = string(key, fallback);
    if (std::find(choices.begin(), choices.end(), value) == choices.end())
    {
        std::string list;
        for (const std::string& c : choices)
        {
            list += (list.empty() ? "" : ", ") + c;
        }
        // A near miss ("stiky") is named, as a mistyped key is.
        const std::string nearest = nearestName(value, choices);
        fail(key, "unknown value '" + value + "'" + (nearest.empty() ? "" : " (did you mean '" + nearest + "'?)") +
                      " (expected one of " + list + ")");
    }
    return value;
}

Vec3 JsonObject::vec3(const std::string& key) const
{
    const nlohmann::json& value = require(key);
    if (!value.is_array() || value.size() != 3 || !value[0].is_number() || !value[1].is_number() ||
        !value[2].is_number())
    {
        fail(key, "expected [x, y, z] (got " + describe(value) + ")");
    }
    const Vec3 v(value[0].get<Real>(), value[1].get<Real>(), value[2].get<Real>());
    if (!v.allFinite())
    {
        fail(key, "expected finite numbers");
    }
    return v;
}

Vec3 JsonObject::vec3(const std::string& key, const Vec3& fallback) const
{
    return find(key) ? vec3(key) : fallback;
}

std::vector<Vec3> JsonObject::vec3List(const std::string& key) const
{
    const nlohmann::json& value = require(key);
    if (!value.is_array())
    {
        fail(key, "expected a list of [x, y, z] points (got " + describe(value) + ")");
    }
    std::vector<Vec3> points;
    for (std::size_t i = 0; i < value.size(); ++i)
    {
        const nlohmann::json& p = value[i];
        if (!p.is_array() || p.size() != 3 || !p[0].is_number() || !p[1].is_number() || !p[2].is_number())
        {
            fail(key, "point " + std::to_string(i) + ": expected [x, y, z] (got " + describe(p) + ")");
        }
        points.emplace_back(p[0].get<Real>(), p[1].get<Real>(), p[2].get<Real>());
    }
    return points;
}

std::optional<JsonObject> JsonObject::object(const std::string& key) const
{
    const nlohmann::json* value = find(key);
    if (!value)
    {
        return std::nullopt;
    }
    return JsonObject(*value, pathOf(key));
}

std::vector<JsonObject> JsonObject::objects(const std::string& key) const
{
    std::vector<JsonObject> result;
    const nlohmann::json* value = find(key);
    if (!value)
    {
        return result;
    }
    if (!value->is_array())
    {
        fail(key, "expected a list [...] (got " + describe(*value) + ")");
    }
    for (std::size_t i = 0; i < value->size(); ++i)
    {
        result.emplace_back((*value)[i], pathOf(key) + "[" + std::to_string(i) + "]");
    }
    return result;
}

std::vector<Real> JsonObject::numbers(const std::string& key) const
{
    std::vector<Real> result;
    const nlohmann::json* value = find(key);
    if (!value)
    {
        return result;
    }
    if (!value->is_array())
    {
        fail(key, "expected a list of numbers (got " + describe(*value) + ")");
    }
    for (const nlohmann::json& element : *value)
    {
        if (!element.is_number() || !std::isfinite(element.get<Real>()))
        {
            fail(key, "expected a list of finite numbers (got " + describe(element) + ")");
        }
        result.push_back(element.get<Real>());
    }
    return result;
}

std::vector<std::string> JsonObject::keys() const
{
    std::vector<std::string> result;
    for (auto it = m_value.begin(); it != m_value.end(); ++it)
    {
        result.push_back(it.key());
    }
    return result;
}

void JsonObject::finish() const
{
    for (auto it = m_value.begin(); it != m_value.end(); ++it)
    {
        if (std::find(m_known.begin(), m_known.end(), it.key()) != m_known.end())
        {
            continue;
        }
        const std::string suggestion = didYouMean(it.key(), m_known);
        std::string message = "unknown key";
        if (!suggestion.empty())
        {
            message += suggestion;
        }
        else if (!m_known.empty())
        {
            std::string list;
            for (const std::string& known : m_known)
            {
                list += (list.empty() ? "" : ", ") + known;
            }
            message += " (known keys: " + list + ")";
        }
        fail(it.key(), message);
    }
}
} // namespace masse::scene
