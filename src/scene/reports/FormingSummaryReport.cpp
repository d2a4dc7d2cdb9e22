// The forming summary: summary.json's "forming" in a forming scene or one that draws the thickness map: the pressure
// at the end, the area sealed onto the mould, and the share of the area thinner than the thickness map's threshold.
// No key of the "report" object asks for it.

#include "scene/reports/ReportRegistry.h"
#include "scene/reports/ThicknessMapReport.h"

namespace masse::scene
{
namespace
{
bool formingSummarised(const SceneSpec& spec)
{
    return spec.forming.enabled || thicknessMapSettings(spec).drawn;
}

class FormingSummary final : public RunningReport
{
public:
    void summarize(const Scene& scene, nlohmann::json& summary) override
    {
        nlohmann::json out = nlohmann::json::object();
        if (const PressureLoad* pressure = scene.pressure())
        {
            out["pressure_pa"] = pressure->currentPressure();
            out["sealed_area_m2"] = pressure->sealedArea();
        }
        if (const SheetThickness* thickness = scene.thickness())
        {
            const Real below = thicknessMapSettings(scene.spec()).thinBelow;
            out["thin_below_ratio"] = below;
            out["thin_area_share"] = thinAreaShare(*thickness, below);
        }
        summary["forming"] = out;
    }
};

constexpr std::string_view formingSummaryKeys[] = {"forming"};
} // namespace

extern const ReportEntry formingSummaryReport = {
    .key = "",
    .enabled = formingSummarised,
    .start = startReport<FormingSummary>,
    .summaryKeys = formingSummaryKeys,
};
} // namespace masse::scene
