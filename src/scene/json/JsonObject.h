#pragma once
/// Typed reading of one JSON object from a scene or material file, with errors that name the key's path.
///
/// Every accessor records the key it was asked for; finish() then refuses any key nobody asked for, suggesting the
/// nearest known one (a typo like "stifness" gets "did you mean 'stiffness'?"). Range checks say the allowed range.

#include "core/Types.h"

#include <nlohmann/json.hpp>

#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace masse::scene
{
class JsonObject
{
public:
    /// `path` names this object in messages ("" for the file's top level, "sheet", "obstacles[2]"...).
    JsonObject(const nlohmann::json& value, std::string path);

    bool has(const std::string& key) const;
    /// This object's path, as given ("" for the file's top level).
    const std::string& path() const { return m_path; }
    /// The key's full path, e.g. "sheet.size".
    std::string pathOf(const std::string& key) const;

    Real number(const std::string& key) const;
    Real number(const std::string& key, Real fallback, Real min = -std::numeric_limits<Real>::infinity(),
                Real max = std::numeric_limits<Real>::infinity()) const;
    /// A number that must be > 0 (and finite).
    Real positive(const std::string& key, Real fallback) const;
    int integer(const std::string& key, int fallback, int min, int max) const;
    bool boolean(const std::string& key, bool fallback) const;
    std::string string(const std::string& key) const;
    std::string string(const std::string& key, const std::string& fallback) const;
    /// One of `choices`.
    std::string choice(const std::string& key, const std::string& fallback,
                       const std::vector<std::string>& choices) const;
    Vec3 vec3(const std::string& key) const;
    Vec3 vec3(const std::string& key, const Vec3& fallback) const;
    std::vector<Vec3> vec3List(const std::string& key) const;

    std::optional<JsonObject> object(const std::string& key) const;
    /// The elements of an array of objects (empty if the key is absent).
    std::vector<JsonObject> objects(const std::string& key) const;
    /// An array of numbers (empty if the key is absent).
    std::vector<Real> numbers(const std::string& key) const;
    /// The raw value, for keys a caller parses itself (recorded as known).
    const nlohmann::json* raw(const std::string& key) const;

    /// Every key of the object, in the file's order.
    std::vector<std::string> keys() const;

    /// Throws InputError for the first key that no accessor asked for, with the nearest known key suggested.
    void finish() const;

    /// Throws InputError with "<path of key>: <message>".
    [[noreturn]] void fail(const std::string& key, const std::string& message) const;

private:
    const nlohmann::json& require(const std::string& key) const;
    const nlohmann::json* find(const std::string& key) const;

    const nlohmann::json& m_value;
    std::string m_path;
    mutable std::vector<std::string> m_known;
};

/// Edit distance between two strings (for suggestions).
std::size_t editDistance(const std::string& a, const std::string& b);
/// Deepest nesting of objects and arrays a JSON file may have (scenes need 5).
constexpr std::size_t maxJsonDepth = 64;
/// Parses a JSON file; throws InputError naming the file and the line of a syntax error, or the file and the key of a
/// number beyond double range or of nesting deeper than maxJsonDepth. A folder is refused by name.
nlohmann::json readJsonFile(const std::string& path);
} // namespace masse::scene
