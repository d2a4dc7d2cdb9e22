// Sheet materials: the modulus and viscosity curves against their defining formulas, validation that names the
// field, and the material files of data/materials.

#include "support/TestSystems.h"

#include "core/InputError.h"
#include "core/material/Material.h"
#include "core/material/WlfLaw.h"
#include "scene/MaterialFile.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <functional>
#include <memory>

using namespace masse;
using masse::test::inputErrorOf;

namespace
{
std::string materialPath(const std::string& name)
{
    return std::string(MASSE_SOURCE_DIR) + "/data/materials/" + name + ".json";
}

const char* const materialNames[] = {"hips", "abs", "pmma", "pet", "pp"};

/// The material's law, which is WlfLaw for the defaults and every shipped file.
const WlfLaw& wlf(const Material& m)
{
    return dynamic_cast<const WlfLaw&>(*m.law);
}

/// Gives the material a copy of its law changed by `change`.
void changeLaw(Material& m, const std::function<void(WlfLaw&)>& change)
{
    auto law = std::make_shared<WlfLaw>(wlf(m));
    change(*law);
    m.law = law;
}

/// A valid material file's text with one line replaced.
std::string writeVariant(const std::string& fileName, const std::string& from, const std::string& to)
{
    std::ifstream in(materialPath("abs"));
    std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t at = text.find(from);
    EXPECT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
    const std::string path = testing::TempDir() + "/" + fileName;
    std::ofstream(path) << text;
    return path;
}
} // namespace

// Glassy well below the transition, rubbery well above (within 1% at 10 widths away), the geometric mean at Tt, and
// falling monotonically in between.
TEST(Material, ModulusFallsFromGlassyToRubberyThroughTheTransition)
{
    const Material m;
    const WlfLaw& law = wlf(m);
    const Real tt = m.transitionTemperature;
    EXPECT_NEAR(modulusAt(m, tt - 10 * law.transitionWidth), law.glassyModulus, 0.01 * law.glassyModulus);
    EXPECT_NEAR(modulusAt(m, tt + 10 * law.transitionWidth), law.rubberyModulus, 0.01 * law.rubberyModulus);
    const Real mean = std::sqrt(law.glassyModulus * law.rubberyModulus);
    EXPECT_NEAR(modulusAt(m, tt), mean, 1e-9 * mean);
    Real previous = modulusAt(m, tt - 8 * law.transitionWidth);
    for (Real t = tt - 8 * law.transitionWidth + 0.5; t < tt + 8 * law.transitionWidth; t += 0.5)
    {
        const Real e = modulusAt(m, t);
        EXPECT_LT(e, previous) << t;
        previous = e;
    }
    // Far outside, the plateaus, with no overflow into NaN.
    EXPECT_NEAR(modulusAt(m, 1e6), law.rubberyModulus, 1e-12 * law.rubberyModulus);
    EXPECT_NEAR(modulusAt(m, 1), law.glassyModulus, 1e-9 * law.glassyModulus);
}

// Above Tt the shift is WLF's; below, Arrhenius with the activation energy that matches WLF's slope at Tt: value
// and slope continuous there (one-sided slopes within 1%). A sheet 20 K below its Tg does not flow (eta > 1e20 Pa s).
TEST(Material, ViscosityFollowsWlfAboveAndArrheniusBelowSmoothly)
{
    const Material m;
    const WlfLaw& law = wlf(m);
    const Real tt = m.transitionTemperature;
    const Real above = 30;
    EXPECT_NEAR(law.log10ShiftAt(m, tt + above), -law.wlfC1 * above / (law.wlfC2 + above), 1e-12);
    EXPECT_EQ(law.log10ShiftAt(m, tt), 0.0);
    const Real d = 1e-3;
    const Real slopeAbove = (law.log10ShiftAt(m, tt + d) - law.log10ShiftAt(m, tt)) / d;
    const Real slopeBelow = (law.log10ShiftAt(m, tt) - law.log10ShiftAt(m, tt - d)) / d;
    EXPECT_NEAR(slopeBelow, slopeAbove, 0.01 * std::abs(slopeAbove));
    EXPECT_NEAR(slopeAbove, -law.wlfC1 / law.wlfC2, 0.01 * law.wlfC1 / law.wlfC2);
    EXPECT_GT(viscosityAt(m, m.glassTransition - 20), 1e20);
    // Clamped: beyond the upper temperature the viscosity stops falling; far below it is capped, not infinite.
    EXPECT_EQ(viscosityAt(m, m.upperTemperature + 100), viscosityAt(m, m.upperTemperature));
    EXPECT_TRUE(std::isfinite(viscosityAt(m, 1.0)));
    EXPECT_EQ(law.log10ShiftAt(m, 1.0), maxLog10Shift);
}

TEST(Material, DefaultsAreValid)
{
    EXPECT_NO_THROW(validate(Material{}));
}

// Every refusal names the field as masse::Material names it (a material file's reader names the key: MaterialFile).
TEST(Material, BadValuesAreRefusedWithTheFieldNamed)
{
    auto refusal = [](const std::function<void(Material&)>& spoil)
    {
        Material m;
        spoil(m);
        return inputErrorOf([&] { validate(m); });
    };
    EXPECT_EQ(refusal([](Material& m) { m.conductivity = -0.1; }).rfind("conductivity: ", 0), 0u);
    EXPECT_EQ(refusal([](Material& m) { m.density = 0; }).rfind("density: ", 0), 0u);
    EXPECT_EQ(refusal([](Material& m) { m.specificHeat = NAN; }).rfind("specificHeat: ", 0), 0u);
    EXPECT_EQ(refusal([](Material& m) { m.glassTransition = celsiusToKelvin(250); }).rfind("glassTransition: ", 0), 0u);
    EXPECT_EQ(refusal([](Material& m) { changeLaw(m, [](WlfLaw& law) { law.glassyModulus = 1e5; }); })
                  .rfind("glassyModulus: ", 0),
              0u);
    EXPECT_EQ(refusal([](Material& m) { changeLaw(m, [](WlfLaw& law) { law.wlfC2 = -5; }); }).rfind("wlfC2: ", 0), 0u);
    EXPECT_EQ(refusal([](Material& m) { changeLaw(m, [](WlfLaw& law) { law.viscosityAtTransition = 0; }); })
                  .rfind("viscosityAtTransition: ", 0),
              0u);
    EXPECT_EQ(refusal([](Material& m) { m.transitionTemperature = m.glassTransition - 10; })
                  .rfind("transitionTemperature: ", 0),
              0u);
    EXPECT_EQ(refusal([](Material& m) { m.forming.normal = m.forming.upper + 10; }).rfind("forming.normal: ", 0), 0u);
    EXPECT_EQ(refusal([](Material& m) { m.forming.set = m.forming.lower + 1; }).rfind("forming.set: ", 0), 0u);
    EXPECT_NE(refusal([](Material& m) { m.conductivity = -0.1; }).find("-0.1"), std::string::npos);
}

// The five files load and validate; hips.json holds the same numbers as masse::Material's defaults.
TEST(MaterialFile, EveryMaterialFileLoads)
{
    for (const char* name : materialNames)
    {
        Material m;
        EXPECT_NO_THROW(m = scene::readMaterialFile(materialPath(name))) << name;
    }
    const Material hips = scene::readMaterialFile(materialPath("hips"));
    const Material defaults;
    EXPECT_EQ(hips.name, defaults.name);
    EXPECT_EQ(hips.density, defaults.density);
    EXPECT_EQ(hips.specificHeat, defaults.specificHeat);
    EXPECT_EQ(hips.conductivity, defaults.conductivity);
    EXPECT_NEAR(hips.glassTransition, defaults.glassTransition, 1e-9);
    EXPECT_NEAR(hips.transitionTemperature, defaults.transitionTemperature, 1e-9);
    EXPECT_NEAR(hips.upperTemperature, defaults.upperTemperature, 1e-9);
    EXPECT_EQ(wlf(hips).glassyModulus, wlf(defaults).glassyModulus);
    EXPECT_EQ(wlf(hips).rubberyModulus, wlf(defaults).rubberyModulus);
    EXPECT_EQ(wlf(hips).transitionWidth, wlf(defaults).transitionWidth);
    EXPECT_EQ(wlf(hips).wlfC1, wlf(defaults).wlfC1);
    EXPECT_EQ(wlf(hips).wlfC2, wlf(defaults).wlfC2);
    EXPECT_EQ(wlf(hips).viscosityAtTransition, wlf(defaults).viscosityAtTransition);
    EXPECT_EQ(wlf(hips).solidActivationEnergy, wlf(defaults).solidActivationEnergy);
    EXPECT_EQ(hips.kelvinModulusRatio, defaults.kelvinModulusRatio);
    EXPECT_EQ(hips.kelvinViscosityRatio, defaults.kelvinViscosityRatio);
    EXPECT_NEAR(hips.forming.set, defaults.forming.set, 1e-9);
    EXPECT_NEAR(hips.forming.lower, defaults.forming.lower, 1e-9);
    EXPECT_NEAR(hips.forming.normal, defaults.forming.normal, 1e-9);
    EXPECT_NEAR(hips.forming.upper, defaults.forming.upper, 1e-9);
}

// A file names its law, or takes the registry's first (wlf, every shipped file's): naming it changes nothing, and a
// name no law is registered under is refused by the key.
TEST(MaterialFile, LawIsChosenFromTheRegistry)
{
    const Material implicitLaw = scene::readMaterialFile(materialPath("abs"));
    const Material namedLaw =
        scene::readMaterialFile(writeVariant("named-law.json", "\"density\"", "\"law\": \"wlf\", \"density\""));
    EXPECT_EQ(materialLaws().front()->name, "wlf");
    EXPECT_EQ(wlf(namedLaw).glassyModulus, wlf(implicitLaw).glassyModulus);
    EXPECT_EQ(wlf(namedLaw).viscosityAtTransition, wlf(implicitLaw).viscosityAtTransition);
    EXPECT_EQ(modulusAt(namedLaw, 400), modulusAt(implicitLaw, 400));
    const std::string path = writeVariant("unknown-law.json", "\"density\"", "\"law\": \"cross\", \"density\"");
    const std::string message = inputErrorOf([&] { scene::readMaterialFile(path); });
    EXPECT_NE(message.find("law"), std::string::npos) << message;
    EXPECT_NE(message.find("wlf"), std::string::npos) << message;
}

// The data make physical sense for forming: at the forming window's normal temperature each sheet relaxes (Maxwell
// time 3 eta / E) within a minute, at its set temperature it holds its shape for more than a day, and at room
// temperature it is glassy (E above 1 GPa).
TEST(MaterialFile, EachMaterialFlowsInItsFormingWindowAndSetsBelowIt)
{
    for (const char* name : materialNames)
    {
        const Material m = scene::readMaterialFile(materialPath(name));
        auto maxwellTime = [&](Real t) { return 3 * viscosityAt(m, t) / modulusAt(m, t); };
        EXPECT_LT(maxwellTime(m.forming.normal), 60.0) << name;
        EXPECT_GT(maxwellTime(m.forming.set), 86400.0) << name;
        EXPECT_GT(modulusAt(m, celsiusToKelvin(20)), 1e9) << name;
    }
}

TEST(MaterialFile, BadFilesNameTheFileAndTheField)
{
    const std::string negative =
        writeVariant("negative_conductivity.json", "\"conductivity\": 0.25", "\"conductivity\": -0.25");
    const std::string message = inputErrorOf([&] { scene::readMaterialFile(negative); });
    EXPECT_EQ(message.rfind(negative + ": conductivity: ", 0), 0u) << message;

    const std::string typo = writeVariant("typo.json", "\"conductivity\"", "\"conductivty\"");
    EXPECT_NE(inputErrorOf([&] { scene::readMaterialFile(typo); }).find("conductivity"), std::string::npos);

    const std::string inverted =
        writeVariant("inverted.json", "\"glass_transition_c\": 110", "\"glass_transition_c\": 250");
    EXPECT_EQ(inputErrorOf([&] { scene::readMaterialFile(inverted); }).rfind(inverted + ": glass_transition_c: ", 0),
              0u);

    const std::string window = writeVariant("window.json", "\"lower_c\": 127", "\"lower_c\": \"warm\"");
    EXPECT_EQ(inputErrorOf([&] { scene::readMaterialFile(window); }).rfind(window + ": forming_window.lower_c: ", 0),
              0u);

    EXPECT_NE(inputErrorOf([&] { scene::readMaterialFile(testing::TempDir() + "/absent.json"); }).find("absent.json"),
              std::string::npos);
}

// Inside a scene the material is an object; errors carry its path.
TEST(MaterialFile, EmbeddedMaterialErrorsCarryTheObjectPath)
{
    nlohmann::json scene = scene::readJsonFile(materialPath("pet"));
    scene["density"] = -1;
    const nlohmann::json wrapper = {{"material", scene}};
    const scene::JsonObject root(wrapper, "");
    const std::optional<scene::JsonObject> object = root.object("material");
    ASSERT_TRUE(object);
    EXPECT_EQ(inputErrorOf([&] { scene::parseMaterial(*object); }).rfind("material.density: ", 0), 0u);
}
