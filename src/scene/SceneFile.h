#pragma once
/// Reading scene files (JSON) into a SceneSpec. Every key, its unit, default and range: data/scenes/README.md.

#include "SceneSpec.h"

#include <nlohmann/json.hpp>

namespace masse::scene
{
/// Reads and checks a scene file; throws InputError "<file>: <key path>: <what is wrong>" for malformed JSON, an
/// unknown key (with the nearest known key suggested), a wrong type or a value out of range, a script action at a
/// negative time or naming a missing obstacle, grab or mass.
SceneSpec loadScene(const std::string& path);

/// The scene file as JSON, with any "extends" base merged in (RFC 7386 merge patch).
nlohmann::json readSceneDocument(const std::string& path, int depth = 0);

/// The same from parsed JSON; `baseDirectory` resolves relative mesh paths, `origin` names the source in messages.
SceneSpec parseScene(const nlohmann::json& document, const std::string& baseDirectory, const std::string& origin);
} // namespace masse::scene
