#include "scene/reports/ThicknessMapReport.h"

#include "scene/reports/ReportRegistry.h"
#include "scene/reports/TopViewMap.h"

#include "core/Format.h"

namespace masse::scene
{
namespace
{
std::any readThicknessMap(const JsonObject& report)
{
    ThicknessMapSettings settings;
    const nlohmann::json& map = *report.raw("thickness_map");
    if (map.is_boolean())
    {
        settings.drawn = map.get<bool>();
        return settings;
    }
    const JsonObject m(map, report.pathOf("thickness_map"));
    settings.drawn = true;
    settings.thinBelow = m.number("below", 0.5, 1e-6, 1.0);
    settings.pixels = m.integer("pixels", 900, 200, 4000);
    if (m.raw("range"))
    {
        const std::vector<Real> range = m.numbers("range");
        if (range.size() != 2 || !(range[0] >= 0) || !(range[1] > range[0]) || !(range[1] <= 10))
        {
            m.fail("range", "expected [low, high] ratios h/h0 with 0 <= low < high <= 10 (default [0, 1])");
        }
        settings.rangeLow = range[0];
        settings.rangeHigh = range[1];
    }
    m.finish();
    return settings;
}

bool thicknessMapDrawn(const SceneSpec& spec)
{
    return thicknessMapSettings(spec).drawn;
}

class ThicknessMap final : public RunningReport
{
public:
    void write(Scene& scene, const std::string& directory, PlotBatch& plots) override
    {
        const SheetThickness* thickness = scene.thickness();
        if (!thickness)
        {
            return;
        }
        const ThicknessMapSettings settings = thicknessMapSettings(scene.spec());
        std::vector<Real> millimetres;
        for (Real h : thickness->thickness())
        {
            millimetres.push_back(1000 * h);
        }
        const Vec3& thinnest = scene.system().particles.position[thickness->thinnestMass()];
        const std::string subtitle =
            "thinnest " + formatNumber("%.3f mm", 1000 * thickness->minimumThickness()) + " (" +
            formatNumber("%.0f%%", 100 * thickness->minimumThickness() / thickness->initialThickness()) + " of " +
            formatNumber("%.2f mm", 1000 * thickness->initialThickness()) + ") at (" +
            formatNumber("%.3f", thinnest.x()) + ", " + formatNumber("%.3f", thinnest.y()) + ", " +
            formatNumber("%.3f", thinnest.z()) + ") m; " +
            formatNumber("%.1f%%", 100 * thinAreaShare(*thickness, settings.thinBelow)) + " of the area below " +
            formatNumber("%.0f%%", 100 * settings.thinBelow) + " of h0";
        const Real h0 = 1000 * thickness->initialThickness();
        drawTopViewMap(plots, scene, millimetres, directory + "/thickness_map.png",
                       scene.spec().name + ": wall thickness, top view", subtitle, "thickness (mm)",
                       "defined (0 '#3b0f70', 0.25 '#8c2981', 0.5 '#de4968', 0.75 '#fe9f6d', 1 '#fcfdbf')",
                       {settings.rangeLow * h0, settings.rangeHigh * h0});
    }
};

} // namespace

extern const ReportEntry thicknessMapReport = {
    .key = "thickness_map",
    .read = readThicknessMap,
    .enabled = thicknessMapDrawn,
    .start = startReport<ThicknessMap>,
};

ThicknessMapSettings thicknessMapSettings(const SceneSpec& spec)
{
    const ThicknessMapSettings* asked = reportSettings<ThicknessMapSettings>(spec, "thickness_map");
    return asked ? *asked : ThicknessMapSettings{};
}

Real thinAreaShare(const SheetThickness& thickness, Real ratio)
{
    Real thin = 0;
    Real total = 0;
    const Real limit = ratio * thickness.initialThickness();
    for (std::size_t i = 0; i < thickness.area().size(); ++i)
    {
        if (thickness.layer()[i] != 0)
        {
            continue;
        }
        total += thickness.area()[i];
        if (thickness.thickness()[i] < limit)
        {
            thin += thickness.area()[i];
        }
    }
    return total > 0 ? thin / total : 0;
}
} // namespace masse::scene
