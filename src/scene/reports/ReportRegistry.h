#pragma once
/// The registry of reports: one entry a report, listed in one table (ReportRegistry.cpp), as the integrators are in
/// core/integrate/Integrator.h. The scene reader reads the "report" object through it, runScene makes, feeds,
/// summarises and writes the reports it lists, and a study learns from it which summary.json values a run adds. A
/// report is its own file in this folder, its line in the table and its row in data/scenes/README.md's `report`
/// table (docs/development.md walks through adding one).

#include "scene/Scene.h"
#include "scene/json/JsonObject.h"
#include "scene/output/Plot.h"

#include <nlohmann/json.hpp>

#include <any>
#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace masse::scene
{
/// One report during one run: made before the first step, told of every step, then asked for its summary.json values
/// and its files. Each does nothing unless the report overrides it.
class RunningReport
{
public:
    virtual ~RunningReport() = default;
    /// After every step, for a report that follows the run (the sag).
    virtual void afterStep(const Scene& scene);
    /// Adds its values to `summary` at the end; the scene's state is finite.
    virtual void summarize(const Scene& scene, nlohmann::json& summary);
    /// Writes its files into `directory`, the run's output folder, after the summary; its plots go into `plots`,
    /// which the run finishes before the folder is complete.
    virtual void write(Scene& scene, const std::string& directory, PlotBatch& plots);
};

/// The `start` of a report whose running part is made from nothing but its type.
template <class Report> std::unique_ptr<RunningReport> startReport(const Scene& /*scene*/)
{
    return std::make_unique<Report>();
}

/// A mass a report's settings name, with the key that names it ("report.sag.mass").
struct NamedMass
{
    std::size_t mass;
    std::string key;
};

struct ReportEntry
{
    /// Its key in the scene's "report" object, or "" for a report no key asks for (made whenever `enabled` says).
    std::string_view key;
    /// Reads its key of the "report" object (present there: `report.raw(key)`, `report.boolean(key, ...)`...) into
    /// its settings, which it finds again with reportSettings; throws InputError naming the key.
    std::any (*read)(const JsonObject& report) = nullptr;
    /// Whether a run of `spec` makes it.
    bool (*enabled)(const SceneSpec& spec) = nullptr;
    /// Makes it for a run of `scene`, before the first step.
    std::unique_ptr<RunningReport> (*start)(const Scene& scene) = nullptr;
    /// The summary.json values it adds, by path ("sag", "final.sag"): a study may ask for them though the summary of
    /// a scene that has not run lacks them.
    std::span<const std::string_view> summaryKeys = {};
    /// The masses its settings name, checked against the sheet with the scene's other mass indices (nullptr: none).
    std::vector<NamedMass> (*massesNamed)(const SceneSpec& spec) = nullptr;
};

/// Every registered report, in the table's order: the order in which the scene reader reads their keys, the runner
/// calls them and their files are written.
std::span<const ReportEntry* const> reports();

/// Reads the scene's "report" object: each registered key it holds, by that key's report; an unknown key is then
/// refused with the nearest registered one suggested.
ReportSpec readReports(const JsonObject& report);

/// The settings the scene's "report" object gave the report of `key` (as its `read` returned them), or nullptr when
/// the object did not name it.
template <class Settings> const Settings* reportSettings(const SceneSpec& spec, std::string_view key)
{
    const auto found = spec.report.asked.find(key);
    return found == spec.report.asked.end() ? nullptr : std::any_cast<Settings>(&found->second);
}

/// The summary.json values the reports a run of `spec` makes add (each enabled report's summaryKeys).
std::vector<std::string> reportSummaryKeys(const SceneSpec& spec);
} // namespace masse::scene
