// report.temperature_map: the sheet's temperature seen from above at the end (temperature_map.png), in a heat scene.

#include "scene/reports/ReportRegistry.h"
#include "scene/reports/TopViewMap.h"

#include "core/Format.h"
#include "core/material/Material.h"

#include <algorithm>

namespace masse::scene
{
namespace
{
std::any readTemperatureMap(const JsonObject& report)
{
    return report.boolean("temperature_map", false);
}

bool temperatureMapDrawn(const SceneSpec& spec)
{
    const bool* drawn = reportSettings<bool>(spec, "temperature_map");
    return drawn && *drawn;
}

class TemperatureMap final : public RunningReport
{
public:
    void write(Scene& scene, const std::string& directory, PlotBatch& plots) override
    {
        if (!scene.thermal())
        {
            return;
        }
        std::vector<Real> celsius;
        for (Real kelvin : scene.thermal()->temperature())
        {
            celsius.push_back(kelvinToCelsius(kelvin));
        }
        const auto [lo, hi] = std::minmax_element(celsius.begin(), celsius.end());
        drawTopViewMap(plots, scene, celsius, directory + "/temperature_map.png",
                       scene.spec().name + ": temperature, top view",
                       "from " + formatNumber("%.1f", *lo) + " to " + formatNumber("%.1f", *hi) + " C",
                       "temperature (C)", "rgb 33,13,10", {});
    }
};

} // namespace

extern const ReportEntry temperatureMapReport = {
    .key = "temperature_map",
    .read = readTemperatureMap,
    .enabled = temperatureMapDrawn,
    .start = startReport<TemperatureMap>,
};
} // namespace masse::scene
