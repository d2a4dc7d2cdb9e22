// `masse check --record` rewrites only a regression scene's "expect" block: the rest of the file (comments, layout,
// key order) stays byte for byte as its author wrote it.

#include "scene/compare/Regression.h"
#include "scene/json/JsonObject.h"
#include "scene/json/JsonText.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <sstream>

using namespace masse;
using namespace masse::scene;

namespace
{
const std::string source = MASSE_SOURCE_DIR;

std::string readText(const std::filesystem::path& path)
{
    std::ifstream in(path);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

void writeText(const std::filesystem::path& path, const std::string& text)
{
    std::ofstream out(path);
    out << text;
}
} // namespace

TEST(RegressionRecord, KeepsCommentsAndLayoutOutsideTheExpectBlock)
{
    const std::filesystem::path path = std::filesystem::path(testing::TempDir()) / "masse-record-keeps-layout.json";
    const std::string head = "// A hand-written regression scene: its comments and layout must survive --record.\n"
                             "{\n"
                             "  \"extends\": \"" +
                             source +
                             "/data/scenes/paper-drop.json\",\n"
                             "  \"sheet\": { \"size\": \"3x2x3\" },   /* the smallest Table 2 sheet */\n"
                             "  \"expect\": ";
    const std::string expect = "{\n"
                               "    // the first contact, reasoned from the free fall\n"
                               "    \"events\": [ { \"name\": \"contact\", \"object\": \"block\", \"sim_time\": 0.5,\n"
                               "                  \"tolerance\": 0.05, \"comment\": \"free fall of 1.09 m\" } ],\n"
                               "    \"final\": { \"kinetic_energy\": { \"max\": 1e-5 } }\n"
                               "  }";
    const std::string tail = ",\n  // a key after the expect block, with \"quotes\" and braces { } in a comment\n"
                             "  \"description\": \"a string with } and // inside\"\n}\n";
    writeText(path, head + expect + tail);

    recordRegression(path.string());

    const std::string after = readText(path);
    ASSERT_GE(after.size(), head.size() + tail.size());
    EXPECT_EQ(after.substr(0, head.size()), head);
    EXPECT_EQ(after.substr(after.size() - tail.size()), tail);
    const nlohmann::json document = readJsonFile(path.string());
    const nlohmann::json& recorded = document["expect"];
    EXPECT_EQ(recorded["final"]["kinetic_energy"]["max"], 1e-5); // bounds kept
    EXPECT_EQ(recorded["final"]["state_hash"].size(), 1u);       // this build type's hash
    ASSERT_GE(recorded["events"].size(), 4u);                    // block, wedge, floor, rest
    EXPECT_EQ(recorded["events"][0]["sim_time"], 0.5);           // a reasoned value is kept
    EXPECT_EQ(recorded["events"][0]["tolerance"], 0.05);
    EXPECT_EQ(document["description"], "a string with } and // inside");
    // And it passes its own check.
    EXPECT_TRUE(runRegression(path.string()).passed());
    std::filesystem::remove(path);
}

// A file without an expect block gets one added at the end of its top-level object; nothing else changes.
TEST(RegressionRecord, AddsAnExpectBlockAtTheEnd)
{
    const std::string text = "{\n  // the sheet\n  \"sheet\": { \"size\": \"3x2x3\" }\n}\n";
    const std::string changed = withTopLevelValue(text, "expect", nlohmann::json{{"in_order", true}});
    const std::size_t end = text.find("\n}");
    EXPECT_EQ(changed.substr(0, end), text.substr(0, end));
    const nlohmann::json parsed = nlohmann::json::parse(changed, nullptr, true, true);
    EXPECT_EQ(parsed["sheet"]["size"], "3x2x3");
    EXPECT_EQ(parsed["expect"]["in_order"], true);
    EXPECT_NE(changed.find("// the sheet"), std::string::npos);

    const std::string empty = withTopLevelValue("{ }", "expect", nlohmann::json::object());
    EXPECT_EQ(nlohmann::json::parse(empty)["expect"], nlohmann::json::object());
}
