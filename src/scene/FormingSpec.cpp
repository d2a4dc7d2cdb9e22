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
} // namespace masse::scene
