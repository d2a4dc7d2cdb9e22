#pragma once
/// Runs a scene headless to its end and writes what it did: summary.json, events.csv and, when asked, frames of the
/// sheet (VTK .vtp and .obj), every file written atomically.

#include "scene/Scene.h"

#include <nlohmann/json.hpp>

#include <optional>
#include <ostream>
#include <string>
#include <vector>

namespace masse::scene
{
struct RunOptions
{
    std::string outDir;       ///< "" writes nothing
    bool showProgress = true; ///< progress on `progressOut`
    bool terminal = false;    ///< progress redrawn in place
};

struct RunResult
{
    nlohmann::json summary;
    Real stepSeconds = 0;     ///< wall time inside Scene::step
    Real overheadSeconds = 0; ///< wall time of the runner itself (progress, events, frame output)
};

/// `masse run`'s --frames-every K and --format F,... (each when given): frames every K steps (0: none), written as vtp
/// unless the scene or `formats` names others. Throws InputError naming the flag of a bad value.
void applyFrameFlags(SceneSpec& spec, std::optional<int> framesEvery, const std::vector<std::string>& formats);

/// Steps the scene until it finishes; writes into options.outDir (created if missing).
RunResult runScene(Scene& scene, const RunOptions& options, std::ostream& progressOut);

/// The summary of a scene as it stands now (see data/scenes/README.md for the fields).
nlohmann::json summarize(Scene& scene, Real wallSeconds);

/// The summary.json values, by path ("runner_overhead", "final.sag"), that a run of `spec` adds or fills as it runs,
/// which summarize() of a scene that has not run lacks: the runner's own and those of the reports the run makes.
std::vector<std::string> summaryKeysAddedByTheRun(const SceneSpec& spec);

/// The implicit solver's statistics as summary.json and `masse bench` report them: mean and largest iterations per
/// step, the steps that stopped at the iteration cap, the final and largest residual (over the tolerance's scale,
/// IntegratorStats), the preconditioner.
nlohmann::json solverSummary(const SolverTally& tally, const ImplicitSettings& settings);

/// A one-line warning for the terminal when steps stopped at the iteration cap, or "" when none did.
std::string solverCapWarning(const SolverTally& tally, const ImplicitSettings& settings);
/// The events as CSV: name,object,sim_time_s,wall_time_s.
std::string eventsCsv(const Scene& scene);
/// "0x" and 16 hex digits of the state hash of every mass's position and velocity.
std::string stateHashText(const Scene& scene);
} // namespace masse::scene
