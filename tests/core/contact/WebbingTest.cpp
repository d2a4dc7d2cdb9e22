// Webbing (issue 12): the places where the sheet lies on itself, found from the positions alone. A sheet dropped into a
// narrow V-shaped trough folds on itself, and the report must name that place, low in the trough, made of the sheet's
// middle strip; a sheet lying flat has none; `masse run` writes the report for scenes with self-collision and not when
// report.webbing is false.

#include "support/MasseCommand.h"

#include "bridge/SelfContactTree.h"
#include "core/contact/SelfContact.h"
#include "scene/Scene.h"
#include "scene/SceneFile.h"
#include "scene/reports/WebbingReport.h"
#include "scene/shapes/BoxShape.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

using namespace masse;
using namespace masse::scene;

namespace
{
const std::string source = MASSE_SOURCE_DIR;

// data/scenes/v-trough.json's trough: the walls' inner faces meet at the apex and rise 75 cm along their slope, at 20
// degrees from the vertical, to the rims.
constexpr Real apexY = -0.8;
const Real halfAngle = 20 * std::acos(Real(-1)) / 180;
const Real rimY = apexY + 0.75 * std::cos(halfAngle);

/// The values of the Int32 point array `name` in a VTP frame, empty when the frame has none.
std::vector<int> vtpIntArray(const std::filesystem::path& file, const std::string& name)
{
    std::ifstream in(file);
    EXPECT_TRUE(in) << file;
    std::string line;
    while (std::getline(in, line) && line.find("Name=\"" + name + "\"") == std::string::npos)
    {
    }
    std::vector<int> values;
    while (std::getline(in, line) && line.rfind("</DataArray>", 0) != 0)
    {
        values.push_back(std::stoi(line));
    }
    return values;
}

void runToEnd(Scene& scene)
{
    while (!scene.finished())
    {
        scene.step();
    }
}
} // namespace

// The sheet, twice as wide as the trough's opening, slides in whole and folds on itself in the narrow bottom of the V.
// The largest place must be that fold: every one of its masses inside the trough (within the walls' V, grown by the
// contact radius, between apex and rims), and made of both halves of the sheet (masses from more than a lattice spacing
// either side of the middle at rest: the legs). With self-collision the legs are still a contact radius apart (no pair
// closer than the radius minus 1%), so the place is found by the report's own distance (1.5 radii).
TEST(Webbing, FoldInANarrowVTroughIsNamedWhereItLies)
{
    const SceneSpec spec = loadScene(source + "/data/scenes/v-trough.json");
    ASSERT_TRUE(reportsWebbing(spec));
    Scene scene(spec);
    runToEnd(scene);
    const std::vector<WebbingPlace> places = webbingPlaces(scene);
    ASSERT_FALSE(places.empty()) << "the sheet did not fold on itself in the trough";
    const WebbingPlace& fold = places.front();
    const Real radius = spec.contact.radius;
    const std::vector<Vec3>& x = scene.system().particles.position;
    const std::vector<Vec3>& rest = scene.lattice().position;
    Real leftmostAtRest = 0;
    Real rightmostAtRest = 0;
    for (const Index i : fold.masses)
    {
        EXPECT_GT(x[i].y(), apexY - radius) << "mass " << i;
        EXPECT_LT(x[i].y(), rimY) << "mass " << i;
        EXPECT_LE(std::abs(x[i].x()), (x[i].y() - apexY) * std::tan(halfAngle) + 1.01 * radius) << "mass " << i;
        leftmostAtRest = std::min(leftmostAtRest, rest[i].x());
        rightmostAtRest = std::max(rightmostAtRest, rest[i].x());
    }
    const Real spacing = scene.lattice().spacingX;
    EXPECT_LT(leftmostAtRest, -spacing);
    EXPECT_GT(rightmostAtRest, spacing);
    EXPECT_LT(std::abs(fold.centre.x()), 0.25 * spacing) << "the trough and the sheet are symmetric about x = 0";

    bridge::SelfContactTree tree;
    SelfContactSettings settings;
    settings.radius = radius;
    SelfContact surface(scene.lattice(), tree, settings);
    std::vector<SelfContactPair> closer;
    surface.pairsWithin(x, 0.99 * radius, closer);
    EXPECT_TRUE(closer.empty()) << closer.size() << " pairs closer than the contact radius minus 1%";

    // The report's own self-contact lists only the springs' exclusions and tests the pairs it meets for the rest: the
    // same pairs as one with every exclusion listed. With a radius of two lattice spacings, the masses near each other
    // at rest (a spring's length and more apart) are many, and both must leave them out.
    SelfContactSettings wide = settings;
    wide.radius = 2 * spacing;
    bridge::SelfContactTree listedTree;
    SelfContact listing(scene.lattice(), listedTree, wide);
    std::vector<SelfContactPair> listed;
    listing.pairsWithin(x, 2 * wide.radius, listed);
    bridge::SelfContactTree testedTree;
    SelfContact tested(scene.lattice(), testedTree, wide, SelfContact::Exclusions::SpringsOnly);
    std::vector<SelfContactPair> testedPairs;
    tested.pairsWithin(x, 2 * wide.radius, testedPairs);
    const auto sorted = [](const std::vector<SelfContactPair>& pairs)
    {
        std::vector<std::pair<Index, Index>> out;
        for (const SelfContactPair& pair : pairs)
        {
            out.emplace_back(pair.vertex, pair.triangle);
        }
        std::sort(out.begin(), out.end());
        return out;
    };
    EXPECT_FALSE(listed.empty()) << "the fold's legs are within four spacings of each other";
    EXPECT_EQ(sorted(testedPairs), sorted(listed)); // their order follows each tree's own history of refits
    // Without the exclusions near at rest (a radius too small for any), the sheet pairs with itself where it is flat.
    SelfContactSettings tiny = settings;
    tiny.radius = 1e-6;
    bridge::SelfContactTree plainTree;
    SelfContact plain(scene.lattice(), plainTree, tiny);
    std::vector<SelfContactPair> unexcluded;
    plain.pairsWithin(x, 2 * wide.radius, unexcluded);
    EXPECT_GT(unexcluded.size(), listed.size() + listed.size() / 2);
}

// The control: the same sheet dropped flat onto a floor lies on nothing but the floor, and its two layers (1 cm apart,
// near each other at rest and so never paired) are not webbing: no place.
TEST(Webbing, ASheetLyingFlatHasNone)
{
    SceneSpec spec = loadScene(source + "/data/scenes/v-trough.json");
    ObstacleSpec floor;
    floor.name = "floor";
    floor.position = Vec3(0, -0.2, 0);
    floor.shape = boxShapeSpec(Vec3(1, 0.05, 1));
    spec.obstacles = {floor};
    spec.run.duration = 1.5;
    Scene scene(spec);
    runToEnd(scene);
    EXPECT_LT(scene.system().particles.position[0].y(), -0.1) << "the sheet did not reach the floor";
    EXPECT_TRUE(webbingPlaces(scene).empty());
}

// `masse run` writes webbing.csv and summary.json's "webbing" (and its count in "final", for an expect block) for a
// scene with self-collision, the largest place on the CSV's first line; with report.webbing false, neither.
TEST(Webbing, RunWritesTheReportUnlessTurnedOff)
{
    const std::filesystem::path folder = std::filesystem::temp_directory_path() / "masse-webbing-test";
    std::filesystem::remove_all(folder);
    const std::string scene = source + "/data/scenes/v-trough.json";
    const Outcome on = runMasse("run " + scene + " --quiet --frames-every 1000 --out " + (folder / "on").string());
    ASSERT_EQ(on.exitCode, 0) << on.output;
    EXPECT_NE(on.output.find("webbing: "), std::string::npos) << on.output;
    std::ifstream summaryFile(folder / "on" / "summary.json");
    const nlohmann::json summary = nlohmann::json::parse(summaryFile);
    ASSERT_TRUE(summary.contains("webbing"));
    EXPECT_GE(summary["webbing"]["places"].get<int>(), 1);
    EXPECT_EQ(summary["final"]["webbing_masses"], summary["webbing"]["masses"]);
    std::ifstream csv(folder / "on" / "webbing.csv");
    std::string header;
    std::string first;
    std::getline(csv, header);
    std::getline(csv, first);
    EXPECT_EQ(header.rfind("place,masses,centre_x_m", 0), 0u) << header;
    EXPECT_EQ(first.rfind("1," + std::to_string(summary["webbing"]["largest"][0]["masses"].get<int>()) + ",", 0), 0u)
        << first;

    // The final frame marks the fold's masses in self_contact (issue 12's "self-contacts in the VTP frames").
    const std::vector<int> selfContact = vtpIntArray(folder / "on" / "frames" / "frame_000100.vtp", "self_contact");
    ASSERT_EQ(selfContact.size(), summary["masses"].get<std::size_t>());
    const long touching = std::count(selfContact.begin(), selfContact.end(), 1);
    EXPECT_GE(touching, 4) << "a closed fold touches at least one vertex-triangle pair";
    EXPECT_EQ(touching + std::count(selfContact.begin(), selfContact.end(), 0), long(selfContact.size()));

    const Outcome off = runMasse("run " + scene +
                                 " --quiet --duration 0.3 --frames-every 1000 --set report.webbing=false "
                                 "--set contact.self_collision=false --out " +
                                 (folder / "off").string());
    ASSERT_EQ(off.exitCode, 0) << off.output;
    EXPECT_TRUE(vtpIntArray(folder / "off" / "frames" / "frame_000010.vtp", "self_contact").empty())
        << "no self_contact array without self-collision";
    EXPECT_FALSE(std::filesystem::exists(folder / "off" / "webbing.csv"));
    std::ifstream offSummary(folder / "off" / "summary.json");
    EXPECT_FALSE(nlohmann::json::parse(offSummary).contains("webbing"));
    std::filesystem::remove_all(folder);
}
