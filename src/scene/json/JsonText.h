#pragma once
/// Editing a JSON document (with // and /* */ comments) as text, so that a tool that changes one value leaves the
/// author's comments, layout and key order everywhere else as they were (`masse check --record`).

#include <nlohmann/json.hpp>

#include <string>

namespace masse::scene
{
/// `text` with the value of the top-level key `key` replaced by `value` (pretty-printed, indented like the key), or,
/// if the key is absent, with `"key": value` added after the last top-level member. Throws InputError if the text is
/// not a JSON object.
std::string withTopLevelValue(const std::string& text, const std::string& key, const nlohmann::json& value);
} // namespace masse::scene
