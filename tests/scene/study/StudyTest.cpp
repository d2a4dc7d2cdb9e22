// Parameter studies without running anything: key paths, --set, the designs, and studies refused before any case
// runs.

#include "scene/study/Study.h"
#include "core/InputError.h"
#include "scene/SceneFile.h"
#include "scene/SceneOverrides.h"
#include "scene/json/JsonPath.h"
#include "scene/study/StudyDesign.h"
#include "scene/study/StudySlurm.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <set>

using namespace masse;
using namespace masse::scene;

namespace
{
const std::string source = MASSE_SOURCE_DIR;

std::string errorOf(const std::function<void()>& action)
{
    try
    {
        action();
    }
    catch (const InputError& e)
    {
        return e.what();
    }
    return "(no error)";
}

/// Writes a study next to the test scenes' folder and returns its path.
std::string writeStudy(const std::string& name, const std::string& text)
{
    const std::filesystem::path folder = std::filesystem::path(testing::TempDir()) / "study-test";
    std::filesystem::create_directories(folder);
    const std::filesystem::path path = folder / (name + ".json");
    std::ofstream(path) << text;
    return path.string();
}

/// A study of the slope scene with the given "vary" (and optional extra top-level keys).
std::string slopeStudy(const std::string& name, const std::string& vary, const std::string& extra = "")
{
    return writeStudy(name, "{ \"scene\": \"" + source + "/data/scenes/slope.json\", \"vary\": " + vary +
                                ", \"outputs\": [\"final.kinetic_energy\"]" + extra + " }");
}
} // namespace

TEST(JsonPath, ParsesKeysAndIndicesAndWritesThemBack)
{
    const JsonPath path = parseJsonPath("heat.heaters[0].power");
    ASSERT_EQ(path.steps.size(), 4u);
    EXPECT_EQ(path.steps[1].key, "heaters");
    EXPECT_TRUE(path.steps[2].isIndex);
    EXPECT_EQ(path.steps[2].index, 0u);
    EXPECT_EQ(path.text(), "heat.heaters[0].power");
    EXPECT_EQ(parseJsonPath("a[1][2].b").text(), "a[1][2].b");
    for (const char* bad : {"", "a..b", "a.", "[0]", "a[x]", "a[]", "a]b", "a[0]b"})
    {
        EXPECT_NE(errorOf([&] { parseJsonPath(bad); }), "(no error)") << bad;
    }
}

TEST(JsonPath, AssignCreatesSectionsButNotListElements)
{
    nlohmann::json document = nlohmann::json::parse(R"({"heat": {"heaters": [{"power": 1}]}})");
    assignAt(document, parseJsonPath("heat.heaters[0].power"), 8000);
    EXPECT_EQ(document["heat"]["heaters"][0]["power"], 8000);
    assignAt(document, parseJsonPath("run.duration"), 2.5);
    EXPECT_EQ(document["run"]["duration"], 2.5);
    EXPECT_NE(errorOf([&] { assignAt(document, parseJsonPath("heat.heaters[1].power"), 1); })
                  .find("heat.heaters has 1 element(s), so no [1]"),
              std::string::npos);
    EXPECT_NE(errorOf([&] { assignAt(document, parseJsonPath("run.duration.x"), 1); }).find("not an object"),
              std::string::npos);
    EXPECT_EQ(*findAt(document, parseJsonPath("heat.heaters[0].power")), 8000);
    EXPECT_EQ(findAt(document, parseJsonPath("heat.heaters[3]")), nullptr);
}

TEST(SetOption, ValuesAreJsonOrPlainText)
{
    EXPECT_EQ(parseKeyOverride("heat.heaters[0].power=8000").value, 8000);
    EXPECT_EQ(parseKeyOverride("integrator.type=implicit").value, "implicit");
    EXPECT_EQ(parseKeyOverride("sheet.size=12x2x12").value, "12x2x12");
    EXPECT_EQ(parseKeyOverride("sheet.min=[0, 1, 2]").value, nlohmann::json::parse("[0, 1, 2]"));
    EXPECT_EQ(parseKeyOverride("name=\"8000\"").value, "8000");
    EXPECT_EQ(parseKeyOverride("x=").value, "");
    EXPECT_NE(errorOf([] { parseKeyOverride("heat.power"); }).find("expected KEY=VALUE"), std::string::npos);
}

TEST(SetOption, ChangesTheSceneAndIsCheckedLikeTheFile)
{
    const std::string scene = source + "/data/scenes/drape-forming.json";
    const SceneSpec base = loadScene(scene);
    const SceneSpec set = loadScene(
        scene, {parseKeyOverride("heat.heaters[0].power=8000"), parseKeyOverride("integrator.type=symplectic")});
    ASSERT_EQ(set.heat.heaterPower.size(), 1u);
    EXPECT_EQ(set.heat.heaterPower[0], 8000);
    EXPECT_NE(base.heat.heaterPower[0], 8000);
    EXPECT_EQ(set.time.integrator, IntegratorKind::SymplecticEuler);

    const std::string unknown = errorOf([&] { loadScene(scene, {parseKeyOverride("heat.heaters[0].powr=8000")}); });
    EXPECT_EQ(unknown.rfind("--set heat.heaters[0].powr=8000: ", 0), 0u) << unknown;
    EXPECT_NE(unknown.find("powr"), std::string::npos) << unknown;
    EXPECT_NE(unknown.find("did you mean 'power'"), std::string::npos) << unknown;
    const std::string refused = errorOf([&] { loadScene(scene, {parseKeyOverride("sheet.size=1x2x1")}); });
    EXPECT_EQ(refused.rfind("--set sheet.size=1x2x1: ", 0), 0u) << refused;
    EXPECT_NE(refused.find("sheet.size: expected NxLxN"), std::string::npos) << refused;
}

TEST(StudyDesign, GridHasEveryCombinationFirstKeySlowest)
{
    const auto cases = gridDesign({{1, 2}, {"a", "b", "c"}});
    ASSERT_EQ(cases.size(), 6u);
    EXPECT_EQ(cases[0], (std::vector<nlohmann::json>{1, "a"}));
    EXPECT_EQ(cases[2], (std::vector<nlohmann::json>{1, "c"}));
    EXPECT_EQ(cases[3], (std::vector<nlohmann::json>{2, "a"}));
    EXPECT_EQ(zipDesign({{1, 2}, {"a", "b"}})[1], (std::vector<nlohmann::json>{2, "b"}));
}

TEST(StudyDesign, RangesByCountAndStepIncludeTheirEnds)
{
    const auto byCount = countValues({10, 30, false}, 3);
    ASSERT_EQ(byCount.size(), 3u);
    EXPECT_DOUBLE_EQ(byCount[2].get<double>(), 30);
    const auto byStep = stepValues({0, 1, false}, 0.1);
    ASSERT_EQ(byStep.size(), 11u); // 0.1 * 10 is 1.0000000000000002 in binary: still counted, within 1e-9 step
    EXPECT_NEAR(byStep.back().get<double>(), 1.0, 1e-12);
    EXPECT_EQ(countValues({1, 4, true}, 4)[1], 2);
}

TEST(StudyDesign, LatinHypercubePutsOneSampleInEveryStratumAndRepeatsWithItsSeed)
{
    const std::vector<StudyRange> ranges = {{0, 10, false}, {100, 200, false}};
    const std::size_t n = 16;
    const auto cases = latinHypercube(ranges, n, 42);
    ASSERT_EQ(cases.size(), n);
    for (std::size_t d = 0; d < ranges.size(); ++d)
    {
        std::set<std::size_t> strata;
        for (const auto& c : cases)
        {
            const double u = (c[d].get<double>() - ranges[d].min) / (ranges[d].max - ranges[d].min);
            ASSERT_GE(u, 0.0);
            ASSERT_LT(u, 1.0);
            strata.insert(std::size_t(u * double(n)));
        }
        EXPECT_EQ(strata.size(), n) << "dimension " << d << ": every stratum exactly once";
    }
    EXPECT_EQ(latinHypercube(ranges, n, 42), cases);
    EXPECT_NE(latinHypercube(ranges, n, 43), cases);
}

TEST(StudyFile, ReadsTheExampleAndItsCases)
{
    const Study study = loadStudy(source + "/data/studies/drape-window.json");
    EXPECT_EQ(study.parameters.size(), 2u);
    EXPECT_GE(study.cases.size(), 6u);
    // The heating time moves the heater switch-off and the mould's start together.
    const nlohmann::json scene = caseDocument(study, study.cases.size() - 1);
    const double off = scene["script"][0]["time"].get<double>();
    EXPECT_EQ(scene["obstacles"][0]["path"][1]["time"].get<double>(), off);
    EXPECT_EQ(scene["obstacles"][0]["path"][2]["time"].get<double>(), off + 4);
}

TEST(StudyFile, BadStudiesAreRefusedNamingTheKey)
{
    // An unknown scene key: refused by the scene's own reader, attributed to the study's key.
    const std::string unknown =
        errorOf([] { loadStudy(slopeStudy("unknown", R"([{"key": "contact.frction", "values": [0.1, 0.2]}])")); });
    EXPECT_NE(unknown.find("vary[0]: contact.frction=0.1"), std::string::npos) << unknown;
    EXPECT_NE(unknown.find("did you mean 'friction'"), std::string::npos) << unknown;

    const std::string empty = errorOf(
        [] {
            loadStudy(
                slopeStudy("empty", R"([{"key": "contact.friction", "range": {"min": 0.5, "max": 0.1, "count": 3}}])"));
        });
    EXPECT_NE(empty.find("vary[0].range.max: empty range"), std::string::npos) << empty;
    const std::string none =
        errorOf([] { loadStudy(slopeStudy("none", R"([{"key": "contact.friction", "values": []}])")); });
    EXPECT_NE(none.find("vary[0].values: empty"), std::string::npos) << none;

    // A value the scene refuses (a negative friction coefficient), in the third case only.
    const std::string refused =
        errorOf([] { loadStudy(slopeStudy("refused", R"([{"key": "contact.friction", "values": [0.1, 0.2, -1]}])")); });
    EXPECT_NE(refused.find("case 2 (contact.friction=-1)"), std::string::npos) << refused;
    EXPECT_NE(refused.find("contact.friction:"), std::string::npos) << refused;

    const std::string output = errorOf(
        []
        {
            loadStudy(writeStudy("output", "{ \"scene\": \"" + source +
                                               "/data/scenes/slope.json\", \"vary\": "
                                               "[{\"key\": \"contact.friction\", \"values\": [0.1]}], \"outputs\": "
                                               "[\"final.kinetic_enrgy\"] }"));
        });
    EXPECT_NE(output.find("outputs[0]: final.kinetic_enrgy: the scene's summary.json has no such value"),
              std::string::npos)
        << output;
    const std::string typo =
        errorOf([] { loadStudy(slopeStudy("typo", R"([{"key": "contact.friction", "valeus": [0.1]}])")); });
    EXPECT_NE(typo.find("vary[0]"), std::string::npos) << typo;
    const std::string lhs = errorOf(
        []
        {
            loadStudy(slopeStudy("lhs", R"([{"key": "contact.friction", "values": [0.1]}])",
                                 R"(, "design": {"latin_hypercube": {"samples": 4, "seed": 1}})"));
        });
    EXPECT_NE(lhs.find("vary[0].values: a Latin hypercube samples ranges"), std::string::npos) << lhs;
}

TEST(StudySlurm, ArrayListCompressesRuns)
{
    EXPECT_EQ(slurmArrayList({0, 1, 2, 3, 5, 7, 8, 9}), "0-3,5,7-9");
    EXPECT_EQ(slurmArrayList({4}), "4");
    SlurmOptions options;
    options.masse = "/opt/masse's/masse";
    options.jobName = "masse-x";
    options.partition = "short";
    options.throttle = 4;
    const std::string script = sbatchScript("/data/study", {0, 1, 2}, options);
    EXPECT_NE(script.find("#SBATCH --array=0-2%4\n"), std::string::npos) << script;
    EXPECT_NE(script.find("#SBATCH --partition=short\n"), std::string::npos) << script;
    EXPECT_NE(script.find("'/opt/masse'\\''s/masse' run scene.json"), std::string::npos) << script;
}
