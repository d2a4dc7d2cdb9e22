#pragma once
/// Regression scenes: a scene file with an "expect" block, run and compared with what it expects.
///
/// "expect": {
///   "events":  [{"name": "contact", "object": "block", "sim_time": 0.51, "tolerance": 0.03}, ...],
///   "in_order": true,                     // the listed events must happen in the listed order
///   "final": {"max_penetration": {"max": 0.001}, "kinetic_energy": {"max": 1e-5},
///             "thickness.min_ratio": {"min": 0.7, "max": 0.76},   // any number of the summary's final block
///             "bbox_min": {"value": [x, y, z], "tolerance": 0.01}, "bbox_max": {...},
///             "state_hash": {"Release": "0x..."}}      // bit-exact, per build type
/// }

#include "scene/Runner.h"
#include "scene/SceneOverrides.h"

#include <string>
#include <vector>

namespace masse::scene
{
/// One comparison: what was checked, expected and got, and whether it passed.
struct Check
{
    std::string what;
    std::string expected;
    std::string actual;
    std::string difference;
    bool passed = false;
};

struct RegressionResult
{
    std::string file;
    std::string scene;
    std::vector<Check> checks;
    Real wallSeconds = 0;
    bool passed() const;
};

/// Runs one regression scene file (with any `--set` keys changed) with the given engine settings, and compares. Throws
/// InputError for a bad file or a bad "expect" block.
RegressionResult runRegression(const std::string& path, const std::vector<KeyOverride>& overrides = {},
                               const EngineSettings& engine = {});

/// Writes the observed values into the file's "expect" block (events with their tolerances kept or 0.03 s, the
/// state hash for this build type, bounds kept): for a maintainer after an intended change. An event expectation
/// with a "comment" is reasoned, not recorded: its time is kept.
void recordRegression(const std::string& path, const EngineSettings& engine = {});

/// The scene files under `path` (a file, or every *.json in a folder, sorted).
std::vector<std::string> regressionFiles(const std::string& path);

/// The table `masse check` prints.
std::string regressionTable(const std::vector<RegressionResult>& results);
} // namespace masse::scene
