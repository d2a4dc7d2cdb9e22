#include "scene/reports/ReportRegistry.h"

namespace masse::scene
{
// Each entry is defined in its report's own file, named beside it in the table.
extern const ReportEntry thicknessMapReport;
extern const ReportEntry temperatureMapReport;
extern const ReportEntry massesCsvReport;
extern const ReportEntry thicknessSectionReport;
extern const ReportEntry sagReport;
extern const ReportEntry webbingReport;
extern const ReportEntry formingSummaryReport;

namespace
{
// The order in which the reader asks for the keys (an unknown key's message lists them in it), the runner calls the
// reports and their files are written.
constexpr const ReportEntry* reportTable[] = {
    &thicknessMapReport,     // ThicknessMapReport.cpp
    &temperatureMapReport,   // TemperatureMapReport.cpp
    &massesCsvReport,        // MassesCsvReport.cpp
    &thicknessSectionReport, // ThicknessSectionReport.cpp
    &sagReport,              // SagReport.cpp
    &webbingReport,          // WebbingReport.cpp
    &formingSummaryReport,   // FormingSummaryReport.cpp
};
} // namespace

void RunningReport::afterStep(const Scene&) {}
void RunningReport::summarize(const Scene&, nlohmann::json&) {}
void RunningReport::write(Scene&, const std::string&, PlotBatch&) {}

std::span<const ReportEntry* const> reports()
{
    return reportTable;
}

ReportSpec readReports(const JsonObject& report)
{
    ReportSpec spec;
    for (const ReportEntry* entry : reportTable)
    {
        if (!entry->key.empty() && report.has(std::string(entry->key)))
        {
            spec.asked.emplace(entry->key, entry->read(report));
        }
    }
    report.finish();
    return spec;
}

std::vector<std::string> reportSummaryKeys(const SceneSpec& spec)
{
    std::vector<std::string> keys;
    for (const ReportEntry* entry : reportTable)
    {
        if (entry->enabled(spec))
        {
            keys.insert(keys.end(), entry->summaryKeys.begin(), entry->summaryKeys.end());
        }
    }
    return keys;
}
} // namespace masse::scene
