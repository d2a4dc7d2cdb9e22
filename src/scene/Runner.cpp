#include "scene/Runner.h"

#include "scene/output/AtomicFile.h"
#include "scene/output/FiniteOutput.h"
#include "scene/output/FrameOutput.h"
#include "scene/output/Plot.h"
#include "scene/output/Progress.h"
#include "scene/reports/ReportRegistry.h"

#include "core/Format.h"
#include "core/InputError.h"
#include "core/StateHash.h"
#include "core/forces/SimdPath.h"
#include "core/parallel/TaskPool.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <sstream>

#ifndef MASSE_BUILD_TYPE
#define MASSE_BUILD_TYPE "unknown"
#endif

namespace masse::scene
{
namespace
{
using Clock = std::chrono::steady_clock;

Real seconds(Clock::duration d)
{
    return std::chrono::duration<Real>(d).count();
}

} // namespace

std::string stateHashText(const Scene& scene)
{
    char text[32];
    std::snprintf(text, sizeof(text), "0x%016llx",
                  static_cast<unsigned long long>(stateHash(scene.system().particles)));
    return text;
}

nlohmann::json solverSummary(const SolverTally& tally, const ImplicitSettings& settings)
{
    return {
        {"preconditioner", std::string(preconditionerName(settings.preconditioner))},
        {"tolerance", settings.tolerance},
        {"max_iterations", settings.maxIterations},
        {"steps", tally.solves},
        {"mean_iterations", tally.meanIterations()},
        {"largest_iterations", tally.largestIterations},
        {"steps_at_iteration_cap", tally.capHits},
        {"final_residual", tally.finalResidual},
        {"largest_residual", tally.largestResidual},
        {"refactorisations", tally.refactorisations},
    };
}

std::string solverCapWarning(const SolverTally& tally, const ImplicitSettings& settings)
{
    if (tally.capHits == 0)
    {
        return "";
    }
    char line[256];
    std::snprintf(line, sizeof(line),
                  "warning: %llu of %llu implicit steps stopped at the iteration cap (%d) short of the tolerance %g "
                  "(largest residual %.3g); raise integrator.max_iterations or shorten dt",
                  static_cast<unsigned long long>(tally.capHits), static_cast<unsigned long long>(tally.solves),
                  settings.maxIterations, settings.tolerance, tally.largestResidual);
    return line;
}

nlohmann::json summarize(Scene& scene, Real wallSeconds)
{
    const SceneSpec& spec = scene.spec();
    const Particles& p = scene.system().particles;
    Vec3 lo = p.position.empty() ? Vec3::Zero() : p.position[0];
    Vec3 hi = lo;
    for (const Vec3& x : p.position)
    {
        lo = lo.cwiseMin(x);
        hi = hi.cwiseMax(x);
    }
    nlohmann::json events = nlohmann::json::array();
    for (const SceneEvent& e : scene.events())
    {
        events.push_back({{"name", e.name}, {"object", e.object}, {"sim_time", e.simTime}, {"wall_time", e.wallTime}});
    }
    const LatticeSpec& lattice = spec.sheet.lattice;
    nlohmann::json final = {
        {"max_penetration", scene.contact().maxPenetration(scene.system())},
        {"kinetic_energy", scene.kineticEnergy()},
        {"bbox_min", {lo.x(), lo.y(), lo.z()}},
        {"bbox_max", {hi.x(), hi.y(), hi.z()}},
        {"state_hash", stateHashText(scene)},
    };
    if (const SheetThickness* thickness = scene.thickness())
    {
        final["thickness"] = {{"initial", thickness->initialThickness()},
                              {"min", thickness->minimumThickness()},
                              {"min_ratio", thickness->minimumThickness() / thickness->initialThickness()},
                              {"min_mass", thickness->thinnestMass()},
                              {"min_layer", thickness->layer()[thickness->thinnestMass()]},
                              {"min_position",
                               {p.position[thickness->thinnestMass()].x(), p.position[thickness->thinnestMass()].y(),
                                p.position[thickness->thinnestMass()].z()}},
                              {"volume_ratio", thickness->volume() / thickness->restVolume()}};
    }
    if (const ThermalModel* thermal = scene.thermal())
    {
        const std::vector<Real>& t = thermal->temperature();
        Real sum = 0;
        for (Real kelvin : t)
        {
            sum += kelvin;
        }
        final["temperature_c"] = {{"min", *std::min_element(t.begin(), t.end()) - 273.15},
                                  {"max", *std::max_element(t.begin(), t.end()) - 273.15},
                                  {"mean", sum / Real(t.size()) - 273.15}};
    }
    nlohmann::json summary = {
        {"scene", spec.name},
        {"scene_file", spec.path},
        {"structure", structureName(lattice.structure)},
        {"size",
         std::to_string(lattice.countX) + "x" + std::to_string(lattice.layers) + "x" + std::to_string(lattice.countZ)},
        {"masses", p.size()},
        {"springs", scene.system().springCount()},
        {"integrator", integratorName(spec.time.integrator)},
        {"threads", scene.simulator().threadCount()},
        {"simd", simdPathName(activeSimdPath())},
        {"dt", spec.time.dt},
        {"steps", scene.steps()},
        {"substeps", scene.simulator().substepCount()},
        {"sim_seconds", scene.time()},
        {"wall_seconds", wallSeconds},
        {"realtime_factor", wallSeconds > 0 ? scene.time() / wallSeconds : 0.0},
        {"contact", contactResponseName(spec.contact.response)},
        {"build_type", MASSE_BUILD_TYPE},
        {"events", events},
        {"final", final},
    };
    if (const SelfContact* self = scene.selfContact())
    {
        // The sheet against itself: touches (vertex-triangle pairs closer than the radius, summed over substeps) in
        // the last frame and in the whole run, and the first one's time and place.
        const SelfContactReport& r = self->report();
        summary["self_contact"] = {
            {"last_frame", r.lastFrame},
            {"last_substep", r.lastSubstep},
            {"total", r.total},
            {"pairs_last_list", r.pairs},
            {"pair_lists", r.queries},
            {"first_time", r.firstTime >= 0 ? nlohmann::json(r.firstTime) : nlohmann::json(nullptr)},
            {"first_mass", r.firstTime >= 0 ? nlohmann::json(r.firstVertex) : nlohmann::json(nullptr)},
            {"first_position", r.firstTime >= 0
                                   ? nlohmann::json({r.firstPosition.x(), r.firstPosition.y(), r.firstPosition.z()})
                                   : nlohmann::json(nullptr)},
        };
    }
    if (const EdgeContact* edges = scene.edgeContact())
    {
        // The sheet's edges and triangles against the obstacles' edges and corners: touches (pairs closer than the
        // radius, summed over substeps) in the last frame and in the whole run, and the first one's time and place.
        const EdgeContactReport& r = edges->report();
        const bool touched = r.firstTime >= 0;
        summary["edge_contact"] = {
            {"last_frame", r.lastFrame},
            {"last_substep", r.lastSubstep},
            {"total", r.total},
            {"edge_pairs_last_list", r.edgePairs},
            {"corner_pairs_last_list", r.cornerPairs},
            {"pair_lists", r.lists},
            {"first_time", touched ? nlohmann::json(r.firstTime) : nlohmann::json(nullptr)},
            {"first_obstacle", touched && r.firstObstacle >= 0
                                   ? nlohmann::json(scene.environment().obstacle(r.firstObstacle).name)
                                   : nlohmann::json(nullptr)},
            {"first_position", touched ? nlohmann::json({r.firstPosition.x(), r.firstPosition.y(), r.firstPosition.z()})
                                       : nlohmann::json(nullptr)},
        };
    }
    if (!isExplicit(spec.time.integrator))
    {
        summary["solver"] = solverSummary(scene.simulator().solverTally(), spec.time.implicit);
    }
    return summary;
}

std::vector<std::string> summaryKeysAddedByTheRun(const SceneSpec& spec)
{
    std::vector<std::string> keys = {"runner_overhead", "solver", "events"};
    const std::vector<std::string> reported = reportSummaryKeys(spec);
    keys.insert(keys.end(), reported.begin(), reported.end());
    return keys;
}

std::string eventsCsv(const Scene& scene)
{
    std::ostringstream out;
    out << "name,object,sim_time_s,wall_time_s\n";
    for (const SceneEvent& e : scene.events())
    {
        char times[64];
        std::snprintf(times, sizeof(times), "%.6f,%.6f", e.simTime, e.wallTime);
        // Names and objects are ours or obstacle names; quote them in case a name holds a comma.
        out << e.name << ",\"" << e.object << "\"," << times << '\n';
    }
    return out.str();
}

void applyFrameFlags(SceneSpec& spec, std::optional<int> framesEvery, const std::vector<std::string>& formats)
{
    if (framesEvery)
    {
        if (*framesEvery < 0 || *framesEvery > 1000000)
        {
            throw InputError("--frames-every: must be a whole number of steps in [0, 1000000] (got " +
                             std::to_string(*framesEvery) + ")");
        }
        spec.output.framesEvery = *framesEvery;
        if (spec.output.formats.empty())
        {
            spec.output.formats = {"vtp"};
        }
    }
    if (!formats.empty())
    {
        for (const std::string& f : formats)
        {
            if (f != "vtp" && f != "obj")
            {
                throw InputError("--format: unknown format '" + f + "' (expected vtp, obj)");
            }
        }
        spec.output.formats = formats;
    }
}

RunResult runScene(Scene& scene, const RunOptions& options, std::ostream& progressOut)
{
    // The reports and frames written between steps run their kernels on the scene's threads too.
    const PoolScope threads(scene.simulator().pool());
    RunResult result;
    const bool writing = !options.outDir.empty();
    const int framesEvery = scene.spec().output.framesEvery;
    std::optional<FrameOutput> frames;
    if (writing)
    {
        std::filesystem::create_directories(options.outDir);
        if (framesEvery > 0)
        {
            frames.emplace(scene, options.outDir);
        }
    }
    if (const std::string warning = scene.substepWarning(); !warning.empty())
    {
        progressOut << "warning: " << warning << "\n";
    }
    Progress progress(progressOut, options.terminal, scene.spec().run.duration);
    const Clock::time_point start = Clock::now();
    Clock::duration inStep{};
    std::size_t eventsShown = 0;
    std::string latest;
    std::vector<std::unique_ptr<RunningReport>> running;
    for (const ReportEntry* entry : reports())
    {
        if (entry->enabled(scene.spec()))
        {
            running.push_back(entry->start(scene));
        }
    }
    while (!scene.finished())
    {
        const Clock::time_point before = Clock::now();
        scene.step();
        inStep += Clock::now() - before;
        for (const std::unique_ptr<RunningReport>& report : running)
        {
            report->afterStep(scene);
        }
        if (frames && scene.steps() % std::uint64_t(framesEvery) == 0)
        {
            frames->write(scene);
        }
        if (options.showProgress)
        {
            for (; eventsShown < scene.events().size(); ++eventsShown)
            {
                const SceneEvent& e = scene.events()[eventsShown];
                char when[32];
                std::snprintf(when, sizeof(when), " at %.2f s", e.simTime);
                latest = e.name + " " + e.object + when;
            }
            progress.update(scene.time(), seconds(Clock::now() - start), latest);
        }
    }
    const Real wall = seconds(Clock::now() - start);
    if (options.showProgress)
    {
        progress.finish(scene.time(), wall, scene.atRest());
    }
    result.stepSeconds = seconds(inStep);
    result.overheadSeconds = wall - result.stepSeconds;
    result.summary = summarize(scene, wall);
    result.summary["runner_overhead"] = result.stepSeconds > 0 ? result.overheadSeconds / result.stepSeconds : 0.0;
    const std::vector<const ScriptAction*> unfired = scene.pendingActions();
    if (!unfired.empty())
    {
        nlohmann::json list = nlohmann::json::array();
        std::string names;
        for (const ScriptAction* action : unfired)
        {
            const std::string name = action->label.empty() ? actionName(action->kind) : action->label;
            list.push_back({{"action", actionName(action->kind)}, {"label", action->label}, {"time", action->time}});
            names += (names.empty() ? "" : ", ") + name + " (" + actionName(action->kind) + " at " +
                     formatNumber(action->time) + " s)";
        }
        result.summary["unfired_actions"] = list;
        progressOut << "warning: " << unfired.size() << " script action(s) never fired, the run ended at "
                    << formatNumber(scene.time()) << " s: " << names << "\n";
    }
    requireFiniteState(scene); // the reports read a finite state only: webbing's broadphase needs finite boxes
    for (const std::unique_ptr<RunningReport>& report : running)
    {
        report->summarize(scene, result.summary);
    }
    requireFiniteJson(result.summary, "summary.json:");
    if (frames)
    {
        frames->finish(scene); // the final state is a frame even when the step count is not a multiple of k
    }
    if (writing)
    {
        PlotBatch plots; // the reports' plots draw side by side while the rest is written
        for (const std::unique_ptr<RunningReport>& report : running)
        {
            report->write(scene, options.outDir, plots);
        }
        writeFileAtomically(options.outDir + "/events.csv", eventsCsv(scene));
        writeFileAtomically(options.outDir + "/summary.json", result.summary.dump(2) + "\n");
        plots.finish();
    }
    return result;
}
} // namespace masse::scene
