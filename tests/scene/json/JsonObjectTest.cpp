// Reading JSON objects: typed access, ranges and unknown keys, each with the key's path in the message.

#include "support/TestSystems.h"

#include "scene/json/JsonObject.h"

#include "core/InputError.h"

#include <gtest/gtest.h>

#include <fstream>
#include <functional>

using namespace masse;
using masse::test::inputErrorOf;
using namespace masse::scene;

TEST(JsonObject, ReadsTypedValuesWithDefaults)
{
    const nlohmann::json value = nlohmann::json::parse(R"({"k": 90.2, "n": 3, "on": true, "v": [1, 2, 3], "s": "x"})");
    JsonObject o(value, "sheet");
    EXPECT_EQ(o.number("k", 0.0, 0.0), 90.2);
    EXPECT_EQ(o.integer("n", 0, 1, 10), 3);
    EXPECT_TRUE(o.boolean("on", false));
    EXPECT_EQ(o.vec3("v"), Vec3(1, 2, 3));
    EXPECT_EQ(o.string("s"), "x");
    EXPECT_EQ(o.number("absent", 7.0), 7.0);
    o.finish();
}

TEST(JsonObject, ErrorsNameThePathAndTheRange)
{
    const nlohmann::json value = nlohmann::json::parse(R"({"stifness": 1, "mass": -1, "size": "big", "v": [1, 2]})");
    JsonObject o(value, "sheet");
    EXPECT_EQ(inputErrorOf([&] { o.positive("mass", 1.0); }), "sheet.mass: must be > 0 (got -1)");
    EXPECT_EQ(inputErrorOf([&] { o.number("mass", 1.0, 0.0, 2.0); }), "sheet.mass: must be in [0, 2] (got -1)");
    EXPECT_EQ(inputErrorOf([&] { o.integer("size", 2, 2, 100); }), "sheet.size: expected a whole number (got \"big\")");
    EXPECT_EQ(inputErrorOf([&] { o.vec3("v"); }), "sheet.v: expected [x, y, z] (got [1,2])");
    EXPECT_EQ(inputErrorOf([&] { o.number("missing"); }), "sheet.missing: is required");
    o.number("stiffness", 1.0);
    EXPECT_EQ(inputErrorOf([&] { o.finish(); }), "sheet.stifness: unknown key (did you mean 'stiffness'?)");
}

TEST(JsonObject, MalformedFilesNameTheLine)
{
    const std::string path = testing::TempDir() + "/malformed.json";
    {
        std::ofstream out(path);
        out << "{\n  \"a\": 1,\n  \"b\": \n}\n";
    }
    const std::string message = inputErrorOf([&] { readJsonFile(path); });
    EXPECT_NE(message.find(path + ": malformed JSON"), std::string::npos) << message;
    EXPECT_NE(message.find("line 4"), std::string::npos) << message;
    EXPECT_NE(inputErrorOf([] { readJsonFile("/no/such.json"); }).find("cannot be read"), std::string::npos);
}
