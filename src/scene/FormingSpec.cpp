#include "scene/FormingSpec.h"

#include "scene/json/FieldKeys.h"
#include "scene/json/JsonObject.h"

#include "core/InputError.h"

namespace masse::scene
{
FormingSpec readForming(const JsonObject& o)
{
    FormingSpec forming;
    forming.enabled = true;
    const nlohmann::json* pressure = o.raw("pressure");
    if (!pressure)
    {
        o.fail("pressure", "required: a pressure in Pa, or a list of {\"time\": s, \"pressure\": Pa} keys");
    }
    if (pressure->is_number())
    {
        forming.pressure.push_back({0, o.number("pressure")});
    }
    else if (pressure->is_array())
    {
        for (const JsonObject& key : o.objects("pressure"))
        {
            forming.pressure.push_back({key.number("time", 0.0, 0.0), key.number("pressure")});
            key.finish();
        }
    }
    else
    {
        o.fail("pressure", "expected a pressure in Pa or a list of {\"time\": s, \"pressure\": Pa} keys");
    }
    checkUnder(o.path(), pressureKeys, [&] { PressureSchedule check(forming.pressure); }); // increasing, finite
    forming.seal = o.boolean("seal", true);
    forming.mould = o.string("mould", "");
    o.finish();
    return forming;
}

FormingReportSpec readFormingReport(const JsonObject& report)
{
    FormingReportSpec spec;
    if (const nlohmann::json* map = report.raw("thickness_map"))
    {
        if (map->is_boolean())
        {
            spec.thicknessMap = map->get<bool>();
        }
        else
        {
            const JsonObject m(*map, report.pathOf("thickness_map"));
            spec.thicknessMap = true;
            spec.thinBelow = m.number("below", 0.5, 1e-6, 1.0);
            spec.mapPixels = m.integer("pixels", 900, 200, 4000);
            if (m.raw("range"))
            {
                const std::vector<Real> range = m.numbers("range");
                if (range.size() != 2 || !(range[0] >= 0) || !(range[1] > range[0]) || !(range[1] <= 10))
                {
                    m.fail("range", "expected [low, high] ratios h/h0 with 0 <= low < high <= 10 (default [0, 1])");
                }
                spec.mapRangeLow = range[0];
                spec.mapRangeHigh = range[1];
            }
            m.finish();
        }
    }
    spec.temperatureMap = report.boolean("temperature_map", false);
    spec.massesCsv = report.boolean("masses_csv", false);
    return spec;
}
} // namespace masse::scene
