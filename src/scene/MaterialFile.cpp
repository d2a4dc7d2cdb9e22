#include "scene/MaterialFile.h"

#include "scene/PlausibleRanges.h"
#include "scene/json/FieldKeys.h"

#include "core/InputError.h"

namespace masse::scene
{
namespace
{
Real celsius(const JsonObject& object, const std::string& key)
{
    return celsiusToKelvin(object.number(key));
}
} // namespace

Material parseMaterial(const JsonObject& object)
{
    Material m;
    m.name = object.string("name");
    object.string("source", "");
    m.density = plausible::density(object, "density");
    m.specificHeat = object.number("specific_heat");
    m.conductivity = object.number("conductivity");
    m.glassTransition = celsius(object, "glass_transition_c");
    m.transitionTemperature = object.has("transition_c") ? celsius(object, "transition_c") : m.glassTransition;
    m.upperTemperature = celsius(object, "upper_c");
    m.glassyModulus = object.number("glassy_modulus");
    m.rubberyModulus = object.number("rubbery_modulus");
    m.transitionWidth = object.number("transition_width", m.transitionWidth);
    m.wlfC1 = object.number("wlf_c1", m.wlfC1);
    m.wlfC2 = object.number("wlf_c2", m.wlfC2);
    m.viscosityAtTransition = object.number("viscosity_at_transition");
    m.solidActivationEnergy = object.number("solid_activation_energy", m.solidActivationEnergy);
    m.kelvinModulusRatio = object.number("kelvin_modulus_ratio", m.kelvinModulusRatio);
    m.kelvinViscosityRatio = object.number("kelvin_viscosity_ratio", m.kelvinViscosityRatio);
    const std::optional<JsonObject> window = object.object("forming_window");
    if (!window)
    {
        object.fail("forming_window", "is required ({set_c, lower_c, normal_c, upper_c})");
    }
    m.forming.set = celsius(*window, "set_c");
    m.forming.lower = celsius(*window, "lower_c");
    m.forming.normal = celsius(*window, "normal_c");
    m.forming.upper = celsius(*window, "upper_c");
    window->finish();
    object.finish();
    checkUnder(object.path(), materialKeys, [&] { validate(m); });
    return m;
}

Material readMaterialFile(const std::string& path)
{
    const nlohmann::json json = readJsonFile(path);
    try
    {
        return parseMaterial(JsonObject(json, ""));
    }
    catch (const InputError& e)
    {
        throw InputError(path + ": " + e.what());
    }
}
} // namespace masse::scene
