#include "scene/MaterialFile.h"

#include "scene/PlausibleRanges.h"
#include "scene/json/FieldKeys.h"

#include "core/InputError.h"
#include "core/material/MaterialLaw.h"

#include <iterator>
#include <vector>

namespace masse::scene
{
namespace
{
Real celsius(const JsonObject& object, const std::string& key)
{
    return celsiusToKelvin(object.number(key));
}

/// A law's keys read from the material's JSON object, with its accessors' messages.
class JsonLawKeys final : public LawKeys
{
public:
    explicit JsonLawKeys(const JsonObject& object) : m_object(object) {}
    Real number(const std::string& key) const override { return m_object.number(key); }
    Real number(const std::string& key, Real fallback) const override { return m_object.number(key, fallback); }

private:
    const JsonObject& m_object;
};

/// The material's fields and its law's, with their keys, for the messages of validate().
std::vector<FieldKey> materialAndLawKeys(const MaterialLawEntry& law)
{
    std::vector<FieldKey> keys(std::begin(materialKeys), std::end(materialKeys));
    for (const LawParameterKey& parameter : law.keys)
    {
        keys.push_back({parameter.field, parameter.key});
    }
    return keys;
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
    std::vector<std::string> lawNames;
    for (const MaterialLawEntry* entry : materialLaws())
    {
        lawNames.emplace_back(entry->name);
    }
    const MaterialLawEntry& law = materialLawNamed(object.choice("law", lawNames.front(), lawNames));
    m.law = law.read(JsonLawKeys(object));
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
    checkUnder(object.path(), materialAndLawKeys(law), [&] { validate(m); });
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
