#pragma once
/// Paths into JSON documents as scene messages write them: `heat.heaters[0].power`, `final.thickness.min_ratio`.
///
/// `--set`, studies and their outputs name keys this way, so a key is written the same in a command, a study and an
/// error message.

#include <nlohmann/json.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace masse::scene
{
/// One step of a path: an object key, or an array index when `isIndex`.
struct JsonPathStep
{
    std::string key;
    std::size_t index = 0;
    bool isIndex = false;
};

struct JsonPath
{
    std::vector<JsonPathStep> steps;
    /// The path as written (`heat.heaters[0].power`).
    std::string text() const;
};

/// Parses `a.b[2].c`; throws InputError "<text>: ..." for an empty key, a bad index or a stray character.
JsonPath parseJsonPath(const std::string& text);

/// The value at the path, or nullptr if some step does not exist.
const nlohmann::json* findAt(const nlohmann::json& document, const JsonPath& path);

/// Sets the value at the path. Missing object keys are created (objects on the way included); an index must name an
/// existing element. Throws InputError naming the step that cannot be followed (an index past the end, an index into
/// something that is not a list, a key into something that is not an object).
void assignAt(nlohmann::json& document, const JsonPath& path, nlohmann::json value);
} // namespace masse::scene
