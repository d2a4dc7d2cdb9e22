// The masse program as a user meets it: output formats, exit codes, and what a run leaves on disk.

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>

namespace
{
struct Outcome
{
    int exitCode;
    std::string output; // stdout and stderr together
};

Outcome masse(const std::string& arguments)
{
    const std::string command = std::string(MASSE_EXECUTABLE) + " " + arguments + " 2>&1";
    FILE* pipe = ::popen(command.c_str(), "r");
    std::string output;
    std::array<char, 512> buffer{};
    while (pipe && std::fgets(buffer.data(), int(buffer.size()), pipe))
    {
        output += buffer.data();
    }
    const int status = pipe ? ::pclose(pipe) : -1;
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}

const std::string source = MASSE_SOURCE_DIR;

std::filesystem::path freshFolder(const std::string& name)
{
    const std::filesystem::path folder = std::filesystem::path(testing::TempDir()) / name;
    std::filesystem::remove_all(folder);
    return folder;
}
} // namespace

TEST(CommandLine, LatticeJsonGivesTableTwoCounts)
{
    const Outcome o = masse("lattice --structure trimm --size 12x2x12 --json");
    ASSERT_EQ(o.exitCode, 0) << o.output;
    const nlohmann::json j = nlohmann::json::parse(o.output);
    EXPECT_EQ(j["structure"], "trimm");
    EXPECT_EQ(j["masses"], 265);
    EXPECT_EQ(j["springs"], 1068);
    EXPECT_EQ(j["layers"], 2);
}

TEST(CommandLine, BadFlagsExitWithTwoAndSayWhy)
{
    const Outcome small = masse("lattice --size 1x2x1");
    EXPECT_EQ(small.exitCode, 2);
    EXPECT_NE(small.output.find("size: expected NxLxN with N >= 2"), std::string::npos) << small.output;
    const Outcome structure = masse("lattice --structure cube");
    EXPECT_EQ(structure.exitCode, 2);
    EXPECT_NE(structure.output.find("unknown structure 'cube'"), std::string::npos) << structure.output;
    EXPECT_EQ(masse("--bogus").exitCode, 2);
    EXPECT_EQ(masse("bench --steps 0").exitCode, 2);
    EXPECT_EQ(masse("bench --integrator rk4").exitCode, 2);
    EXPECT_EQ(masse("run").exitCode, 2); // the scene argument is required
    const Outcome help = masse("--help");
    EXPECT_EQ(help.exitCode, 0);
    for (const char* command : {"lattice", "bench", "demo", "run", "paper", "check"})
    {
        EXPECT_NE(help.output.find(command), std::string::npos) << command;
    }
}

TEST(CommandLine, BadSceneLeavesNoOutputFolder)
{
    const std::filesystem::path out = freshFolder("bad-run");
    const Outcome o = masse("run " + source + "/tests/bad-scenes/unknown-key.json --out " + out.string());
    EXPECT_EQ(o.exitCode, 2);
    EXPECT_NE(o.output.find("sheet.stifness: unknown key"), std::string::npos) << o.output;
    EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(CommandLine, RunWritesSummaryEventsAndFrames)
{
    const std::filesystem::path out = freshFolder("slope-run");
    const Outcome o = masse("run " + source + "/data/scenes/slope.json --out " + out.string() +
                            " --frames-every 50 --format vtp,obj --quiet");
    ASSERT_EQ(o.exitCode, 0) << o.output;

    std::ifstream in(out / "summary.json");
    const nlohmann::json s = nlohmann::json::parse(in);
    for (const char* key : {"scene", "masses", "springs", "dt", "steps", "sim_seconds", "wall_seconds",
                            "realtime_factor", "events", "final"})
    {
        EXPECT_TRUE(s.contains(key)) << key;
    }
    for (const char* key : {"max_penetration", "kinetic_energy", "bbox_min", "bbox_max", "state_hash"})
    {
        EXPECT_TRUE(s["final"].contains(key)) << key;
    }
    EXPECT_EQ(s["masses"], 25);
    bool stopper = false;
    for (const auto& e : s["events"])
    {
        for (const char* key : {"name", "object", "sim_time", "wall_time"})
        {
            EXPECT_TRUE(e.contains(key)) << key;
        }
        stopper = stopper || (e["name"] == "contact" && e["object"] == "stopper");
    }
    EXPECT_TRUE(stopper);

    std::ifstream csv(out / "events.csv");
    std::string header;
    std::getline(csv, header);
    EXPECT_EQ(header, "name,object,sim_time,wall_time");

    int vtp = 0;
    int obj = 0;
    for (const auto& entry : std::filesystem::directory_iterator(out / "frames"))
    {
        vtp += entry.path().extension() == ".vtp" ? 1 : 0;
        obj += entry.path().extension() == ".obj" ? 1 : 0;
        EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << "left over: " << entry.path();
    }
    EXPECT_GE(vtp, 3);
    EXPECT_EQ(vtp, obj);
    std::ifstream frame(out / "frames" / "frame_000000.vtp");
    std::stringstream text;
    text << frame.rdbuf();
    EXPECT_NE(text.str().find("<VTKFile type=\"PolyData\""), std::string::npos);
    EXPECT_NE(text.str().find("NumberOfPoints=\"25\""), std::string::npos);
}

TEST(CommandLine, BenchPrintsOneJsonLine)
{
    const Outcome o = masse("bench --structure trimm --size 8x2x8 --steps 1 --repeat 1");
    ASSERT_EQ(o.exitCode, 0) << o.output;
    const nlohmann::json j = nlohmann::json::parse(o.output);
    for (const char* key : {"masses", "springs", "steps", "wall_seconds", "spring_steps_per_second"})
    {
        EXPECT_TRUE(j.contains(key)) << key;
    }
    EXPECT_EQ(j["masses"], 113);
    EXPECT_GT(j["spring_steps_per_second"].get<double>(), 0.0);
}
