#pragma once
/// A live run saved as a scene file that `masse run` replays bit for bit (the viewer's "save run"): the scene's
/// document as it was read (its "extends" merged, the paths of its files made absolute, the --set keys and the flags
/// applied), the actions added while it ran after its own script, and the time it was saved at as its duration. The
/// replay takes the same steps: the viewer steps with the scene's dt whatever its frame rate, an added action fires at
/// the start of the first frame at or after its time (the frame after the one it was added at), as the same action
/// read from the file does, and the same scene gives the same bits at any thread count.

#include "scene/SceneOverrides.h"
#include "scene/SceneSpec.h"

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace masse::scene
{
/// Where a running scene came from: its file and the flags it was read with.
struct RunSource
{
    std::string path;
    SceneFlags flags;
};

/// The action as a scene file's script item writes it (readScriptAction reads it back; times and values to the
/// last bit). A move's keys keep their rotation only to rounding.
nlohmann::json actionDocument(const ScriptAction& action);

/// The scene file of a run from `source` with the `added` actions, saved at `duration` s. Throws InputError as
/// reading the scene does (a file changed since it was read may no longer be a scene).
nlohmann::json savedRunDocument(const RunSource& source, const std::vector<ScriptAction>& added, Real duration);
} // namespace masse::scene
