// The masse program as a user meets it: output formats, exit codes, and what a run leaves on disk.

#include "support/MasseCommand.h"
#include "support/Sanitizers.h"

#include "core/StepStage.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/file.h>
#include <sys/wait.h>
#include <unistd.h>

namespace
{
const std::string source = MASSE_SOURCE_DIR;

std::filesystem::path freshFolder(const std::string& name)
{
    const std::filesystem::path folder = std::filesystem::path(testing::TempDir()) / name;
    std::filesystem::remove_all(folder);
    return folder;
}

std::string readText(const std::filesystem::path& path)
{
    std::ifstream in(path);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

/// The id of a process that has exited (forked, reaped): what a run killed with -9 leaves in its leftovers' names.
std::string deadProcess()
{
    const pid_t child = ::fork();
    if (child == 0)
    {
        ::_exit(0);
    }
    int status = 0;
    ::waitpid(child, &status, 0);
    return std::to_string(child);
}

/// The JSON line `masse bench ARGUMENTS` prints (an empty object, the command's failure reported, if it fails).
nlohmann::json benchJson(const std::string& arguments)
{
    const Outcome outcome = runMasse("bench " + arguments);
    EXPECT_EQ(outcome.exitCode, 0) << outcome.output;
    const std::size_t start = outcome.output.find('{');
    return outcome.exitCode == 0 && start != std::string::npos ? nlohmann::json::parse(outcome.output.substr(start))
                                                               : nlohmann::json::object();
}
} // namespace

TEST(CommandLine, LatticeJsonGivesTableTwoCounts)
{
    const Outcome o = runMasse("lattice --structure trimm --size 12x2x12 --json");
    ASSERT_EQ(o.exitCode, 0) << o.output;
    const nlohmann::json j = nlohmann::json::parse(o.output);
    EXPECT_EQ(j["structure"], "trimm");
    EXPECT_EQ(j["masses"], 265);
    EXPECT_EQ(j["springs"], 1068);
    EXPECT_EQ(j["layers"], 2);
}

TEST(CommandLine, BadFlagsExitWithTwoAndSayWhy)
{
    const Outcome small = runMasse("lattice --size 1x2x1");
    EXPECT_EQ(small.exitCode, 2);
    EXPECT_NE(small.output.find("--size: expected NxLxN with N >= 2"), std::string::npos) << small.output;
    const Outcome structure = runMasse("lattice --structure cube");
    EXPECT_EQ(structure.exitCode, 2);
    EXPECT_NE(structure.output.find("--structure: unknown structure 'cube'"), std::string::npos) << structure.output;
    EXPECT_EQ(runMasse("--bogus").exitCode, 2);
    EXPECT_EQ(runMasse("bench --steps 0").exitCode, 2);
    EXPECT_EQ(runMasse("bench --integrator rk4").exitCode, 2);
    EXPECT_EQ(runMasse("run").exitCode, 2); // the scene argument is required
    const Outcome help = runMasse("--help");
    EXPECT_EQ(help.exitCode, 0);
    for (const char* command : {"lattice", "bench", "demo", "run", "paper", "check", "compare"})
    {
        EXPECT_NE(help.output.find(command), std::string::npos) << command;
    }
}

TEST(CommandLine, BadSceneLeavesNoOutputFolder)
{
    const std::filesystem::path out = freshFolder("bad-run");
    const Outcome o = runMasse("run " + source + "/tests/bad-scenes/unknown-key.json --out " + out.string());
    EXPECT_EQ(o.exitCode, 2);
    EXPECT_NE(o.output.find("sheet.stifness: unknown key"), std::string::npos) << o.output;
    EXPECT_FALSE(std::filesystem::exists(out));
}

TEST(CommandLine, RunWritesSummaryEventsAndFrames)
{
    const std::filesystem::path out = freshFolder("slope-run");
    const Outcome o = runMasse("run " + source + "/data/scenes/slope.json --out " + out.string() +
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
    EXPECT_EQ(header, "name,object,sim_time_s,wall_time_s");

    int vtp = 0;
    int obj = 0;
    for (const auto& entry : std::filesystem::directory_iterator(out / "frames"))
    {
        // The sheet's frames; the obstacles' own VTP files (for ParaView) sit beside them.
        const bool sheetFrame = entry.path().filename().string().rfind("frame_", 0) == 0;
        vtp += sheetFrame && entry.path().extension() == ".vtp" ? 1 : 0;
        obj += sheetFrame && entry.path().extension() == ".obj" ? 1 : 0;
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
    const Outcome o = runMasse("bench --structure trimm --size 8x2x8 --steps 1 --repeat 1");
    ASSERT_EQ(o.exitCode, 0) << o.output;
    const nlohmann::json j = nlohmann::json::parse(o.output);
    for (const char* key : {"masses", "springs", "steps", "wall_seconds", "spring_steps_per_second"})
    {
        EXPECT_TRUE(j.contains(key)) << key;
    }
    EXPECT_EQ(j["masses"], 113);
    EXPECT_GT(j["spring_steps_per_second"].get<double>(), 0.0);
}

// `masse bench` times a scene file: by default data/scenes/bench-free-fall.json, with --contact bench-contact.json (the
// sheet resting on two boxes, so it reports contact figures with masses touching), or the file given, whose
// obstacles it times too; a file and --contact together are refused.
TEST(CommandLine, BenchTimesTheSceneItIsGiven)
{
    const Outcome freeFall = runMasse("bench --size 8x2x8 --steps 1 --repeat 1");
    ASSERT_EQ(freeFall.exitCode, 0) << freeFall.output;
    const nlohmann::json f = nlohmann::json::parse(freeFall.output);
    EXPECT_NE(f["scene"].get<std::string>().find("bench-free-fall.json"), std::string::npos) << f["scene"];
    EXPECT_FALSE(f.contains("contact"));

    const Outcome resting = runMasse("bench --contact --size 8x2x8 --steps 1 --repeat 1");
    ASSERT_EQ(resting.exitCode, 0) << resting.output;
    const nlohmann::json c = nlohmann::json::parse(resting.output);
    EXPECT_NE(c["scene"].get<std::string>().find("bench-contact.json"), std::string::npos) << c["scene"];
    ASSERT_TRUE(c.contains("contact"));
    EXPECT_GT(c["contact"]["touching_masses"].get<int>(), 0);

    const Outcome drop = runMasse("bench " + source + "/data/scenes/paper-drop.json --size 8x2x8 --steps 1 --repeat 1");
    ASSERT_EQ(drop.exitCode, 0) << drop.output;
    const nlohmann::json d = nlohmann::json::parse(drop.output);
    EXPECT_NE(d["scene"].get<std::string>().find("paper-drop.json"), std::string::npos) << d["scene"];
    EXPECT_TRUE(d.contains("contact"));
    EXPECT_EQ(d["masses"], 113);

    const Outcome both = runMasse("bench " + source + "/data/scenes/paper-drop.json --contact --steps 1");
    EXPECT_EQ(both.exitCode, 2);
    EXPECT_NE(both.output.find("--contact"), std::string::npos) << both.output;
}

// On an implicit scene `masse bench` says where the step goes in the implicit solve: each solve's matrix, the
// preconditioner's refreshes and following, the conjugate gradient's iterations. The vacuum cup's first frames at
// 16x2x16 (the sheet landing on the mould, its constraints changing every frame) take iterations and assembly every
// solve; the parts are each within the rounds' wall time and together no more than it, and the warm-up step holds the
// pattern's analysis. An explicit scene has no solver stages.
TEST(CommandLine, BenchSaysWhereTheImplicitSolvesTimeGoes)
{
    const nlohmann::json c =
        benchJson(source + "/data/scenes/vacuum-forming-cup.json --size 16x2x16 --steps 5 --repeat 1");
    ASSERT_TRUE(c.contains("solver_stages")) << c.dump();
    const nlohmann::json& stages = c["solver_stages"];
    const double wall = c["wall_seconds"].get<double>();
    EXPECT_GT(stages["assembly_seconds"].get<double>(), 0.0);
    EXPECT_GT(stages["iterations_seconds"].get<double>(), 0.0);
    EXPECT_GE(stages["preconditioner_seconds"].get<double>(), 0.0);
    EXPECT_EQ(stages["analysis_seconds"].get<double>(), 0.0);
    const double parts = stages["assembly_seconds"].get<double>() + stages["preconditioner_seconds"].get<double>() +
                         stages["iterations_seconds"].get<double>();
    EXPECT_LE(parts, wall);
    EXPECT_NEAR(stages["share_of_step"].get<double>(), parts / wall, 1e-9);
    EXPECT_NEAR(stages["iterations_share"].get<double>(), stages["iterations_seconds"].get<double>() / wall, 1e-9);

    EXPECT_FALSE(benchJson("--size 8x2x8 --steps 1 --repeat 1").contains("solver_stages"));
}

// `masse bench` counts the preconditioner's refactorisations in its timed rounds, as `masse run` counts a run's: the
// vacuum cup at 16x2x16, its first 31 frames run, refactor as often as its first frame (the bench's warm-up step) and
// then the bench's 30 timed frames do; the mould's arrival makes some in those frames.
TEST(CommandLine, BenchCountsTheRefactorisationsOfItsRounds)
{
    const std::string cup = source + "/data/scenes/vacuum-forming-cup.json --size 16x2x16";
    const auto refactorisationsOfRun = [&](const char* duration, const char* name)
    {
        const std::filesystem::path out = std::filesystem::temp_directory_path() / name;
        std::filesystem::remove_all(out);
        const Outcome o = runMasse("run " + cup + " --set run.duration=" + duration + " --quiet --out " + out.string());
        EXPECT_EQ(o.exitCode, 0) << o.output;
        std::ifstream file(out / "summary.json");
        const nlohmann::json summary = nlohmann::json::parse(file);
        std::filesystem::remove_all(out);
        return summary["solver"]["refactorisations"].get<long long>();
    };
    const long long firstFrame = refactorisationsOfRun("0.03", "masse-bench-refactorisations-1");
    const long long thirtyOneFrames = refactorisationsOfRun("0.93", "masse-bench-refactorisations-31");
    const nlohmann::json bench = benchJson(cup + " --steps 30 --repeat 1");
    ASSERT_GT(thirtyOneFrames, firstFrame);
    EXPECT_EQ(bench["solver"]["refactorisations"].get<long long>(), thirtyOneFrames - firstFrame);
}

// `masse bench` says where the frame goes, stage by stage of the frame's table (docs/step.md): every stage is named,
// each within the rounds' wall time, together no more than it and most of it (the rest is the rounds' own loop), and
// the implicit solve's stages lie within `integrate`. On the drape-forming sheet under its heater the heat model's
// step (`endFrame`) and the springs' refresh (`beginFrame`) take time; an explicit free fall's frame is its
// `integrate` stage's substeps.
TEST(CommandLine, BenchSaysWhereTheFrameGoesStageByStage)
{
    const nlohmann::json d = benchJson(source + "/data/scenes/drape-forming.json --size 16x2x16 --steps 5 --repeat 1");
    ASSERT_TRUE(d.contains("step_stages")) << d.dump();
    const nlohmann::json& stages = d["step_stages"];
    const double wall = d["wall_seconds"].get<double>();
    double sum = 0;
    for (const masse::StepStageEntry& entry : masse::stepStageTable)
    {
        ASSERT_TRUE(stages.contains(std::string(entry.name))) << entry.name;
        const double seconds = stages[std::string(entry.name)]["seconds"].get<double>();
        EXPECT_GE(seconds, 0.0) << entry.name;
        EXPECT_NEAR(stages[std::string(entry.name)]["share"].get<double>(), seconds / wall, 1e-9) << entry.name;
        sum += seconds;
    }
    EXPECT_LE(sum, wall);
    EXPECT_GT(sum, 0.5 * wall);
    EXPECT_GT(stages["endFrame"]["seconds"].get<double>(), 0.0);
    EXPECT_GT(stages["beginFrame"]["seconds"].get<double>(), 0.0);
    const nlohmann::json& solver = d["solver_stages"];
    EXPECT_LE(solver["assembly_seconds"].get<double>() + solver["preconditioner_seconds"].get<double>() +
                  solver["iterations_seconds"].get<double>(),
              stages["integrate"]["seconds"].get<double>());

    const nlohmann::json f = benchJson("--size 8x2x8 --steps 1 --repeat 1");
    ASSERT_TRUE(f.contains("step_stages")) << f.dump();
    EXPECT_GT(f["step_stages"]["integrate"]["seconds"].get<double>(), 0.0);
}

// `masse compare` on the reference landing (the 8 x 2 x 8 Table 1 sheet onto a box at dt = 0.03 s), cut to 2 s:
// compare.json holds, for MaSSE and for each Bullet run asked, its events, penetration, tunnelled nodes, kinetic
// energy and wall time, and for each Bullet run its distance to MaSSE; the plots and the series are written whole;
// the table names every run. And, through compare.json: MaSSE's deepest penetration is no larger than Bullet's at the
// same step (measured: MaSSE about 1e-13 m, Bullet 0.026 m with 1 pass and 0.028 m with 4).
TEST(CommandLine, CompareWritesBothEnginesFiguresAndPlots)
{
    const std::filesystem::path out = freshFolder("compare-landing");
    const Outcome o = runMasse("compare " + source + "/data/scenes/box-landing.json --out " + out.string() +
                               " --duration 2 --bullet-iterations 1,4 --quiet");
    ASSERT_EQ(o.exitCode, 0) << o.output;
    for (const char* header : {"MaSSE (symplectic)", "Bullet (piterations=1)", "Bullet (piterations=4)",
                               "max penetration (mm)", "tunnelled nodes", "wall ms per simulated s", "Approximations"})
    {
        EXPECT_NE(o.output.find(header), std::string::npos) << header;
    }
    for (const char* file : {"compare.json", "series.csv", "penetration.png", "kinetic_energy.png", "distance.png"})
    {
        EXPECT_GT(std::filesystem::file_size(out / file), 100u) << file;
    }
    for (const auto& entry : std::filesystem::directory_iterator(out))
    {
        EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << "left over: " << entry.path();
    }

    std::ifstream in(out / "compare.json");
    const nlohmann::json c = nlohmann::json::parse(in);
    for (const char* key :
         {"scene", "masses", "springs", "dt", "frames", "sim_seconds", "contact_radius", "engines", "approximations"})
    {
        EXPECT_TRUE(c.contains(key)) << key;
    }
    EXPECT_EQ(c["masses"], 113);
    EXPECT_NEAR(c["sim_seconds"].get<double>(), 2.0, 1e-9); // 66 steps of 0.03 s and a last one shortened to end on 2 s
    const nlohmann::json& engines = c["engines"];
    ASSERT_EQ(engines.size(), 3u);
    EXPECT_EQ(engines[0]["engine"], "masse");
    for (const nlohmann::json& e : engines)
    {
        for (const char* key : {"label", "settings", "events", "penetration", "tunnelled", "kinetic_energy",
                                "wall_ms_per_simulated_second", "frames"})
        {
            EXPECT_TRUE(e.contains(key)) << e["label"] << " " << key;
        }
        for (const char* key : {"max", "mean"})
        {
            EXPECT_TRUE(e["penetration"].contains(key)) << key;
        }
        EXPECT_TRUE(e["tunnelled"].contains("count"));
        EXPECT_GT(e["wall_ms_per_simulated_second"].get<double>(), 0.0) << e["label"];
        EXPECT_EQ(e["frames"], 67);
        bool box = false;
        for (const nlohmann::json& event : e["events"])
        {
            box = box || (event["name"] == "contact" && event["object"] == "box");
        }
        EXPECT_TRUE(box) << e["label"];
        if (e["engine"] == "bullet")
        {
            EXPECT_TRUE(e["distance_to_masse"]["final"].contains("rms"));
            EXPECT_TRUE(e["distance_to_masse"]["final"].contains("max"));
            EXPECT_FALSE(e["distance_to_masse"]["events"].empty());
            EXPECT_LE(engines[0]["penetration"]["max"].get<double>(), e["penetration"]["max"].get<double>())
                << e["label"];
            EXPECT_GT(e["penetration"]["max"].get<double>(), 0.01) << e["label"];
        }
    }
    EXPECT_EQ(engines[1]["settings"]["piterations"], 1);
    EXPECT_EQ(engines[2]["settings"]["piterations"], 4);
    ASSERT_FALSE(c["approximations"].empty());
    for (const nlohmann::json& a : c["approximations"])
    {
        EXPECT_TRUE(a["subject"].is_string());
        EXPECT_FALSE(a["message"].get<std::string>().empty());
    }
}

// A bad "bullet" key, or a bad flag, stops `masse compare` with exit code 2 and a message naming it, before the
// output folder is made.
// As `masse run` does, `masse compare` says before it starts that a step will take over a thousand substeps: the
// comparison's sheet stiffened 2,000-fold (2e5 N/m) needs about 1,350 symplectic substeps a step.
TEST(CommandLine, CompareSaysWhenAStepNeedsOverAThousandSubsteps)
{
    const std::filesystem::path out = freshFolder("compare-stiff");
    const Outcome o =
        runMasse("compare " + source + "/data/scenes/box-landing.json --duration 0.03 --quiet" +
                 " --set sheet.stiffness.planar=2e5 --set sheet.stiffness.inter_layer=2e5 --out " + out.string());
    ASSERT_EQ(o.exitCode, 0) << o.output;
    EXPECT_NE(o.output.find("warning: the symplectic integrator needs"), std::string::npos) << o.output;
    const Outcome soft = runMasse(
        "compare " + source + "/data/scenes/box-landing.json --duration 0.03 --quiet --force --out " + out.string());
    ASSERT_EQ(soft.exitCode, 0) << soft.output;
    EXPECT_EQ(soft.output.find("warning:"), std::string::npos) << soft.output;
}

TEST(CommandLine, CompareRefusesBadBulletSettingsBeforeWriting)
{
    const std::filesystem::path out = freshFolder("compare-bad");
    const std::pair<std::string, std::string> cases[] = {
        {source + "/tests/bad-scenes/bullet-klst.json", "bullet.kLST: must be in (0, 1] (got 1.5)"},
        {source + "/tests/bad-scenes/bullet-unknown-key.json", "bullet.kLTS: unknown key (did you mean 'kLST'?)"},
        {source + "/data/scenes/box-landing.json --bullet-iterations 0",
         "--bullet-iterations: each count must be a whole number in [1, 1000] (got 0)"},
        {source + "/data/scenes/box-landing.json --bullet-substeps 0",
         "--bullet-substeps: must be a whole number in [1, 10000] (got 0)"},
    };
    for (const auto& [arguments, expected] : cases)
    {
        const Outcome o = runMasse("compare " + arguments + " --out " + out.string() + " --quiet");
        EXPECT_EQ(o.exitCode, 2) << arguments << ": " << o.output;
        EXPECT_NE(o.output.find(expected), std::string::npos) << o.output;
        EXPECT_FALSE(std::filesystem::exists(out)) << arguments;
    }
}

// `masse demo --headless --out DIR` prints the Figure 18 table and plots it, as the README says.
TEST(CommandLine, DemoHeadlessPlotsFigure18)
{
    const std::filesystem::path folder = freshFolder("demo-headless");
    const Outcome o = runMasse("demo --headless --out " + folder.string());
    ASSERT_EQ(o.exitCode, 0) << o.output;
    EXPECT_NE(o.output.find("12x2x12"), std::string::npos) << o.output;
    EXPECT_TRUE(std::filesystem::exists(folder / "figure18.csv"));
    ASSERT_TRUE(std::filesystem::exists(folder / "figure18.png"));
    EXPECT_GT(std::filesystem::file_size(folder / "figure18.png"), 1000u);
}

// Flags out of range, and steps the integrator cannot take, exit with 2 naming the flag and the range before the output
// folder exists.
TEST(CommandLine, BadStepsAndDurationsAreRefusedBeforeAnythingIsWritten)
{
    const std::filesystem::path out = freshFolder("bad-steps");
    const std::pair<std::string, std::string> cases[] = {
        {"--dt 0", "--dt: must be a number of seconds in [1e-06, 1] (got '0')"},
        {"--dt inf", "--dt: must be a number of seconds in [1e-06, 1] (got 'inf')"},
        {"--dt 1000", "--dt: must be a number of seconds in [1e-06, 1] (got '1000')"},
        {"--duration 0", "--duration: must be a number of seconds in (0, 1e+06] (got '0')"},
        {"--duration inf", "--duration: must be a number of seconds in (0, 1e+06] (got 'inf')"},
        {"--dt 1e-6 --duration 1e6", "--duration / --dt: 1e+06 s in steps of 1e-06 s is 1e+12 steps"},
        {"--frames-every -5", "--frames-every: must be a whole number of steps in [0, 1000000] (got -5)"},
    };
    for (const auto& [flags, expected] : cases)
    {
        const Outcome o = runMasse("run " + source + "/data/scenes/slope.json " + flags + " --out " + out.string());
        EXPECT_EQ(o.exitCode, 2) << flags << ": " << o.output;
        EXPECT_NE(o.output.find(expected), std::string::npos) << o.output;
        EXPECT_FALSE(std::filesystem::exists(out)) << flags;
    }
    const Outcome stiff =
        runMasse("run " + source + "/tests/bad-scenes/stiff-explicit-step.json --frames-every 1 --out " + out.string());
    EXPECT_EQ(stiff.exitCode, 2) << stiff.output;
    EXPECT_NE(stiff.output.find("integrator.dt: the symplectic integrator needs"), std::string::npos) << stiff.output;
    EXPECT_FALSE(std::filesystem::exists(out)) << "the first frame was written before the step was refused";
}

// A second run into a folder holding a run is refused; with --force it replaces it whole, so no frame of the first run
// stays beside the second's summary.
TEST(CommandLine, RunsIntoTheSameFolderNeverMix)
{
    const std::filesystem::path out = freshFolder("mixed");
    const std::string run = "run " + source + "/data/scenes/slope.json --duration 0.3 --quiet --out " + out.string();
    ASSERT_EQ(runMasse(run + " --frames-every 5").exitCode, 0);
    ASSERT_TRUE(std::filesystem::exists(out / "frames" / "frame_000005.vtp"));
    const Outcome again = runMasse(run);
    EXPECT_EQ(again.exitCode, 2) << again.output;
    EXPECT_NE(again.output.find("already holds a run (summary.json)"), std::string::npos) << again.output;
    const Outcome forced = runMasse(run + " --frames-every 0 --force");
    ASSERT_EQ(forced.exitCode, 0) << forced.output;
    EXPECT_TRUE(std::filesystem::exists(out / "summary.json"));
    EXPECT_FALSE(std::filesystem::exists(out / "frames")) << "frames of the first run kept beside the second's";
    for (const auto& entry : std::filesystem::directory_iterator(out.parent_path()))
    {
        EXPECT_EQ(entry.path().filename().string().find(".mixed."), std::string::npos) << entry.path();
    }
}

// A scene file giving a gravity no machine has (1e100, 1e200 or 1e308 m/s^2) is refused when read: exit code 2, the
// file and the key named, nothing written. Run, 1e100 and 1e308 would end with exit code 0 and every mass at y = 0 (the
// floor at -2.81 m), and 1e200 would overflow the run. (HostileInput has the runs the library can still be given.)
TEST(CommandLine, AGravityBeyondAnyMachineIsRefusedNamingTheKey)
{
    const std::filesystem::path folder = freshFolder("beyond-range");
    std::filesystem::create_directories(folder);
    for (const char* gravity : {"1e100", "1e308"})
    {
        const std::filesystem::path scene = folder / (std::string("gravity-") + gravity + ".json");
        std::ofstream(scene) << R"({ "sheet": { "size": "4x2x4" }, "environment": { "gravity": [0, -)" << gravity
                             << R"(, 0] }, "run": { "duration": 0.3, "stop_at_rest": false } })";
        const std::filesystem::path out = folder / (std::string("out-") + gravity);
        const Outcome o = runMasse("run " + scene.string() + " --quiet --out " + out.string());
        EXPECT_EQ(o.exitCode, 2) << o.output;
        EXPECT_NE(o.output.find(scene.string() + ": environment.gravity: " + std::string(gravity).replace(1, 1, "e+") +
                                " m/s^2 is beyond the plausible 1000 m/s^2"),
                  std::string::npos)
            << o.output;
        EXPECT_FALSE(std::filesystem::exists(out));
    }
    const std::filesystem::path out = folder / "out-1e200";
    const Outcome o =
        runMasse("run " + source + "/tests/bad-scenes/gravity-beyond-range.json --quiet --out " + out.string());
    EXPECT_EQ(o.exitCode, 2) << o.output;
    EXPECT_FALSE(std::filesystem::exists(out));
}

// A heater's power in kilowatts typed as watts (through --set as through the file) is refused when the scene is read:
// exit code 2, the key and the likely mistake named, nothing written.
TEST(CommandLine, AHeaterPowerInKilowattsIsRefusedNamingTheKey)
{
    const std::filesystem::path out = freshFolder("heater-kilowatts");
    const Outcome o = runMasse("run " + source + "/data/scenes/sag.json --set heat.heaters[0].power=10 --quiet --out " +
                               out.string());
    EXPECT_EQ(o.exitCode, 2) << o.output;
    EXPECT_NE(o.output.find("heat.heaters[0].power: 10 W from a 0.8 m x 0.8 m panel is 15.625 W/m^2"),
              std::string::npos)
        << o.output;
    EXPECT_NE(o.output.find("did you mean 10000 (10 kW)?"), std::string::npos) << o.output;
    EXPECT_FALSE(std::filesystem::exists(out));
}

// Output paths that cannot be written are refused before the experiment runs, so masse paper does not run all five
// sizes and then fail on a file given as --out.
TEST(CommandLine, UnwritableOutputsAreRefusedUpFront)
{
    const std::filesystem::path folder = freshFolder("unwritable");
    std::filesystem::create_directories(folder);
    {
        std::ofstream(folder / "file") << "a file";
    }
    const Outcome paper = runMasse("paper --out " + (folder / "file").string());
    EXPECT_EQ(paper.exitCode, 2) << paper.output;
    EXPECT_NE(paper.output.find("--out: '" + (folder / "file").string() + "' exists and is not a folder"),
              std::string::npos)
        << paper.output;
    EXPECT_EQ(paper.output.find("done"), std::string::npos) << "the experiment ran before the output was checked";
    const Outcome longName =
        runMasse("run " + source + "/data/scenes/slope.json --out " + (folder / std::string(300, 'x')).string());
    EXPECT_EQ(longName.exitCode, 2) << longName.output;
    EXPECT_NE(longName.output.find("has a name of 300 bytes"), std::string::npos) << longName.output;
}

// A read-only --out (the folder itself, its parent, or a missing parent inside a read-only one) is refused with exit
// code 2 and one line naming the path, before the scene runs. The suite runs as root in CI, where permission bits stop
// no write (CAP_DAC_OVERRIDE), so the read-only folder is one where no one, root included, can create anything: the
// masse process's own folder in procfs, /proc/self. Nothing can be written there, so what this checks is when and how
// the run is refused: with every frame written (--frames-every 1), a check left to the first write or to the end would
// stop the run with exit code 1 and another message, after it had started.
TEST(CommandLine, AReadOnlyOutputIsRefusedBeforeTheRun)
{
    const std::string run = "run " + source + "/data/scenes/slope.json --duration 0.3 --frames-every 1 --out ";
    for (const std::string out : {"/proc/self", "/proc/self/masse-out", "/proc/self/masse-out/run"})
    {
        const Outcome o = runMasse(run + out);
        EXPECT_EQ(o.exitCode, 2) << out << ":\n" << o.output;
        EXPECT_EQ(o.output.rfind("masse: --out: '" + out + "' cannot be ", 0), 0u) << o.output;
        EXPECT_EQ(std::count(o.output.begin(), o.output.end(), '\n'), 1) << "the run started:\n" << o.output;
    }
    // masse paper ran all five sheet sizes before it failed on its --out.
    const Outcome paper = runMasse("paper --out /proc/self/masse-paper");
    EXPECT_EQ(paper.exitCode, 2) << paper.output;
    EXPECT_EQ(paper.output.rfind("masse: --out: '/proc/self/masse-paper' cannot be ", 0), 0u) << paper.output;
    EXPECT_EQ(std::count(paper.output.begin(), paper.output.end(), '\n'), 1) << "the experiment started:\n"
                                                                             << paper.output;
    // masse sweep stopped with exit code 1 and the library's "filesystem error: cannot create directories".
    const Outcome sweep =
        runMasse("sweep " + source + "/tests/studies/slope-friction.json --out /proc/self/masse-sweep");
    EXPECT_EQ(sweep.exitCode, 2) << sweep.output;
    EXPECT_EQ(sweep.output.rfind("masse: --out: '/proc/self/masse-sweep' cannot be written (", 0), 0u) << sweep.output;
    EXPECT_EQ(std::count(sweep.output.begin(), sweep.output.end(), '\n'), 1) << "the study started:\n" << sweep.output;
}

// MaSSE deletes only what it wrote. A folder holding the user's own files (the scene beside its results, notes.txt) is
// refused, with --force or without, by a message naming them, and they stay; so is the folder of an earlier run the
// user has added a file to. Without the file, --force replaces the earlier run.
TEST(CommandLine, OutputFoldersHoldingTheUsersFilesAreRefusedAndKept)
{
    const std::filesystem::path out = freshFolder("users-files");
    std::filesystem::create_directories(out);
    std::filesystem::copy_file(source + "/data/scenes/slope.json", out / "s.json");
    std::ofstream(out / "notes.txt") << "my notes";
    const std::string run = "run " + (out / "s.json").string() + " --duration 0.1 --quiet --out " + out.string();
    for (const std::string flags : {"", " --force"})
    {
        const Outcome o = runMasse(run + flags);
        EXPECT_EQ(o.exitCode, 2) << flags << ": " << o.output;
        EXPECT_NE(o.output.find("notes.txt"), std::string::npos) << flags << ": " << o.output;
        EXPECT_NE(o.output.find("s.json"), std::string::npos) << flags << ": " << o.output;
        EXPECT_EQ(readText(out / "notes.txt"), "my notes") << flags;
        EXPECT_EQ(readText(out / "s.json"), readText(source + "/data/scenes/slope.json")) << flags;
        EXPECT_FALSE(std::filesystem::exists(out / "summary.json")) << flags << ": the run mixed into the folder";
    }

    const std::filesystem::path results = freshFolder("users-file-in-a-run");
    const std::string again =
        "run " + source + "/data/scenes/slope.json --duration 0.1 --quiet --force --out " + results.string();
    ASSERT_EQ(runMasse(again).exitCode, 0);
    const std::string first = readText(results / "summary.json");
    std::ofstream(results / "notes.txt") << "what I saw";
    const Outcome refused = runMasse(again);
    EXPECT_EQ(refused.exitCode, 2) << refused.output;
    EXPECT_NE(refused.output.find("notes.txt"), std::string::npos) << refused.output;
    EXPECT_EQ(readText(results / "notes.txt"), "what I saw");
    EXPECT_EQ(readText(results / "summary.json"), first);
    std::filesystem::remove(results / "notes.txt");
    const Outcome forced = runMasse(again);
    EXPECT_EQ(forced.exitCode, 0) << forced.output;
}

// Only leftovers in MaSSE's own form are removed, never an entry a user may have named so: a folder thesis.tmp-N, a
// file notes.tmp-N or .x.partial-N, a folder .run1.old-N (N a process that has exited).
TEST(CommandLine, EntriesBesideTheOutputFolderNamedLikeLeftoversStay)
{
    const std::filesystem::path folder = freshFolder("users-leftover-names");
    const std::string dead = deadProcess();
    std::filesystem::create_directories(folder / ("thesis.tmp-" + dead) / "chapters");
    std::ofstream(folder / ("thesis.tmp-" + dead) / "chapters" / "one.tex") << "chapter one";
    std::ofstream(folder / ("notes.tmp-" + dead)) << "notes";
    std::ofstream(folder / (".x.partial-" + dead)) << "x";
    std::filesystem::create_directories(folder / (".run1.old-" + dead));
    std::ofstream(folder / (".run1.old-" + dead) / "old.txt") << "old";
    const Outcome o = runMasse("run " + source + "/data/scenes/slope.json --duration 0.1 --quiet --out " +
                               (folder / "run1").string());
    ASSERT_EQ(o.exitCode, 0) << o.output;
    EXPECT_EQ(readText(folder / ("thesis.tmp-" + dead) / "chapters" / "one.tex"), "chapter one");
    EXPECT_EQ(readText(folder / ("notes.tmp-" + dead)), "notes");
    EXPECT_EQ(readText(folder / (".x.partial-" + dead)), "x");
    EXPECT_EQ(readText(folder / (".run1.old-" + dead) / "old.txt"), "old");
}

// A --force run killed between its two renames leaves the earlier result under the old-folder's name and the new one in
// its staging folder, with no folder under the output's own name. The next run into the folder restores the earlier
// result (and, without --force, refuses to replace it) instead of deleting both.
TEST(CommandLine, AForcedReplacementKilledBetweenItsRenamesIsRestored)
{
    const std::filesystem::path out = freshFolder("interrupted");
    for (const auto& entry : std::filesystem::directory_iterator(out.parent_path()))
    {
        if (entry.path().filename().string().rfind(".interrupted.", 0) == 0) // an earlier test run's, killed
        {
            std::filesystem::remove_all(entry.path());
        }
    }
    const std::string run = "run " + source + "/data/scenes/slope.json --duration 0.1 --quiet --out " + out.string();
    ASSERT_EQ(runMasse(run).exitCode, 0);
    const std::string earlier = readText(out / "summary.json");
    ASSERT_FALSE(earlier.empty());

    // The state the kill leaves, made by hand: the names and markers a forced run of process `dead` gives them.
    const std::string dead = deadProcess();
    const std::filesystem::path old = out.parent_path() / (".interrupted.masse-old-" + dead + "-0123abcd");
    const std::filesystem::path partial = out.parent_path() / (".interrupted.masse-partial-" + dead + "-89abcdef");
    std::filesystem::rename(out, old);
    std::filesystem::create_directories(partial);
    std::error_code noManifest; // the marker a staging folder holds
    std::filesystem::copy_file(old / ".masse-manifest.json", partial / ".masse-manifest.json", noManifest);
    std::ofstream(partial / "summary.json") << "{\"the new run\": true}\n";

    const Outcome again = runMasse(run);
    EXPECT_EQ(again.exitCode, 2) << again.output;
    EXPECT_NE(again.output.find("already holds a run"), std::string::npos) << again.output;
    EXPECT_EQ(readText(out / "summary.json"), earlier) << "the earlier result was not restored";
    EXPECT_FALSE(std::filesystem::exists(old));
    EXPECT_FALSE(std::filesystem::exists(partial));
}

// Runs into one folder take a lock; a run started while another writes there is refused with exit code 2, so two runs
// cannot both print "wrote" while the folder holds one result. Here the test holds the lock the way a run does; then
// two runs started together end with one result and one refusal.
TEST(CommandLine, ASecondRunIntoTheSameFolderIsRefusedWhileTheFirstWrites)
{
    const std::filesystem::path out = freshFolder("locked");
    const std::string run =
        "run " + source + "/data/scenes/slope.json --duration 0.1 --quiet --force --out " + out.string();
    ASSERT_EQ(runMasse(run).exitCode, 0);
    const std::string earlier = readText(out / "summary.json");
    {
        const std::filesystem::path lockFile = out.parent_path() / ".locked.masse-lock";
        const int fd = ::open(lockFile.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
        ASSERT_GE(fd, 0);
        ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);
        const Outcome refused = runMasse(run);
        EXPECT_EQ(refused.exitCode, 2) << refused.output;
        EXPECT_NE(refused.output.find("another masse run is writing"), std::string::npos) << refused.output;
        EXPECT_EQ(readText(out / "summary.json"), earlier);
        std::filesystem::remove(lockFile);
        ::close(fd);
    }

    const std::filesystem::path fresh = freshFolder("locked-together");
    const std::string command = std::string(MASSE_EXECUTABLE) + " run " + source +
                                "/data/scenes/slope.json --duration 0.3 --quiet --out " + fresh.string() + " 2>&1";
    FILE* first = ::popen(command.c_str(), "r");
    FILE* second = ::popen(command.c_str(), "r");
    ASSERT_TRUE(first && second);
    std::string output;
    std::array<char, 512> buffer{};
    for (FILE* pipe : {first, second})
    {
        while (std::fgets(buffer.data(), int(buffer.size()), pipe))
        {
            output += buffer.data();
        }
    }
    const int a = ::pclose(first);
    const int b = ::pclose(second);
    ASSERT_TRUE(WIFEXITED(a) && WIFEXITED(b)) << output;
    std::array<int, 2> codes = {WEXITSTATUS(a), WEXITSTATUS(b)};
    std::sort(codes.begin(), codes.end());
    EXPECT_EQ(codes[0], 0) << output;
    EXPECT_EQ(codes[1], 2) << output;
    std::size_t wrote = 0;
    for (std::size_t at = output.find("wrote "); at != std::string::npos; at = output.find("wrote ", at + 1))
    {
        ++wrote;
    }
    EXPECT_EQ(wrote, 1u) << output;
    EXPECT_FALSE(nlohmann::json::parse(readText(fresh / "summary.json"), nullptr, false).is_discarded());
}

// --size is applied after the scene file is read; the mass indices the scene names are checked against the sheet that
// is built, whatever made it. A 16 x 2 x 16 sheet's masses 128 and 200 do not exist in the 113 of an 8 x 2 x 8 one, and
// a run that used them could abort, crash, corrupt the heap or report a sag of 0.
TEST(CommandLine, MassIndicesAreCheckedAgainstTheSizeGivenOnTheCommandLine)
{
    const std::filesystem::path folder = freshFolder("size-override");
    std::filesystem::create_directories(folder);
    const std::string sheet = R"("sheet": { "size": "16x2x16" }, "run": { "duration": 0.05 })";
    const std::string grab = R"("path": [ { "position": [0, 1, 0] } ])";
    const std::pair<std::string, std::string> scenes[] = {
        {R"({ "sheet": { "size": "16x2x16", "pinned": { "masses": [128] } }, "run": { "duration": 0.05 } })",
         "sheet.pinned.masses: 128 is beyond the sheet's 113 masses"},
        {"{ " + sheet + R"(, "script": [ { "time": 0, "action": "grab", "mass": 200, )" + grab + " } ] }",
         "script[0].mass: 200 is beyond the sheet's 113 masses"},
        {"{ " + sheet + R"(, "script": [ { "time": 0, "action": "pin", "masses": { "masses": [200] } } ] })",
         "script[0].masses.masses: 200 is beyond the sheet's 113 masses"},
        {"{ " + sheet + R"(, "report": { "sag": { "mass": 200 } } })",
         "report.sag.mass: 200 is beyond the sheet's 113 masses"},
    };
    int i = 0;
    for (const auto& [text, expected] : scenes)
    {
        const std::filesystem::path scene = folder / ("scene-" + std::to_string(++i) + ".json");
        std::ofstream(scene) << text;
        ASSERT_EQ(runMasse("run " + scene.string() + " --quiet").exitCode, 0) << text << " is valid as it is";
        const std::filesystem::path out = folder / ("out-" + std::to_string(i));
        const Outcome o = runMasse("run " + scene.string() + " --size 8x2x8 --quiet --out " + out.string());
        EXPECT_EQ(o.exitCode, 2) << text << ":\n" << o.output;
        EXPECT_NE(o.output.find(scene.string() + ": " + expected), std::string::npos) << o.output;
        EXPECT_NE(o.output.find("(--size 8x2x8)"), std::string::npos) << o.output;
        EXPECT_FALSE(std::filesystem::exists(out)) << text;
    }
}

// A thread the system cannot start (a 1 GB address-space limit, and 1024 threads of 2 MB stacks or more) is refused
// naming --threads, with exit code 2 and nothing written, rather than ending in std::terminate.
TEST(CommandLine, ThreadsTheSystemCannotStartAreRefusedNamingTheFlag)
{
    if (masse::test::underAddressSanitizer || masse::test::underThreadSanitizer)
    {
        // Skipped under the sanitizers: their shadow memory alone exceeds the address-space limit, so nothing would
        // start.
        GTEST_SKIP() << "the sanitizers reserve far more address space than the limit this test sets";
    }
    const std::filesystem::path out = freshFolder("too-many-threads");
    const std::string command = "sh -c 'ulimit -v 1000000 && exec " + std::string(MASSE_EXECUTABLE) + " run " + source +
                                "/data/scenes/slope.json --duration 0.1 --quiet --threads 1024 --out " + out.string() +
                                "' 2>&1";
    FILE* pipe = ::popen(command.c_str(), "r");
    ASSERT_NE(pipe, nullptr);
    std::string output;
    std::array<char, 512> buffer{};
    while (std::fgets(buffer.data(), int(buffer.size()), pipe))
    {
        output += buffer.data();
    }
    const int status = ::pclose(pipe);
    ASSERT_TRUE(WIFEXITED(status)) << "killed by a signal:\n" << output;
    EXPECT_EQ(WEXITSTATUS(status), 2) << output;
    EXPECT_EQ(output.rfind("masse: --threads: the system cannot start 1024 threads", 0), 0u) << output;
    EXPECT_FALSE(std::filesystem::exists(out));
}

// An empty value (`--dt ''`, most often a shell variable never set) is refused naming the flag, not taken as "not
// given" with the run going on with the scene's own value; so is --threads 0, outside the 1 to 1024 the message gives.
// Each exits with code 2, nothing written.
TEST(CommandLine, EmptyFlagValuesAndZeroThreadsAreRefused)
{
    const std::filesystem::path folder = freshFolder("empty-flags");
    int i = 0;
    for (const std::string flag :
         {"--dt ''", "--duration ''", "--size ''", "--integrator ''", "--threads ''", "--threads 0", "--threads 1025"})
    {
        const std::filesystem::path out = folder / ("out-" + std::to_string(i++));
        const Outcome o =
            runMasse("run " + source + "/data/scenes/slope.json --quiet " + flag + " --out " + out.string());
        EXPECT_EQ(o.exitCode, 2) << flag << ":\n" << o.output;
        EXPECT_EQ(o.output.rfind("masse: " + flag.substr(0, flag.find(' ')) + ": ", 0), 0u) << flag << ":\n"
                                                                                            << o.output;
        EXPECT_FALSE(std::filesystem::exists(out)) << flag;
    }
}

// Messages name where the mistake is: a mistyped command gets the nearest command, not "A subcommand is required"; a
// --set of a list under a misspelt name gets the nearest name, not "heat.heater is a null"; a --set that makes another
// key wrong (a square lattice that has one layer, where the scene's size has two) names the --set, not the scene file
// alone.
TEST(CommandLine, MistakesAreNamedWhereTheyAreWithTheNearestName)
{
    const Outcome command = runMasse("runn " + source + "/data/scenes/slope.json");
    EXPECT_EQ(command.exitCode, 2) << command.output;
    EXPECT_EQ(command.output.rfind("masse: unknown command 'runn' (did you mean 'run'?)", 0), 0u) << command.output;

    const std::filesystem::path out = freshFolder("named-mistakes");
    const Outcome list =
        runMasse("run " + source + "/data/scenes/sag.json --set heat.heater[0].power=1 --out " + out.string());
    EXPECT_EQ(list.exitCode, 2) << list.output;
    EXPECT_NE(list.output.find("--set heat.heater[0].power=1: heat.heater[0].power: heat has no list 'heater' (did "
                               "you mean 'heaters'?)"),
              std::string::npos)
        << list.output;

    // The names a scene gives its heaters and obstacles are suggested too, where a script or a key refers to one.
    const Outcome heater =
        runMasse("run " + source + "/data/scenes/sag.json --set script[0].heater=panle --out " + out.string());
    EXPECT_EQ(heater.exitCode, 2) << heater.output;
    EXPECT_NE(heater.output.find("no heater is named 'panle' (did you mean 'panel'?)"), std::string::npos)
        << heater.output;
    const Outcome obstacle = runMasse(
        "run " + source + "/data/scenes/vacuum-forming-cup.json --set forming.mould=mold " + "--out " + out.string());
    EXPECT_EQ(obstacle.exitCode, 2) << obstacle.output;
    EXPECT_NE(obstacle.output.find("no obstacle is named 'mold' (did you mean 'mould'?)"), std::string::npos)
        << obstacle.output;

    const std::string knife = source + "/data/scenes/knife-edge.json";
    const Outcome other = runMasse("run " + knife + " --set sheet.structure=square2d --out " + out.string());
    EXPECT_EQ(other.exitCode, 2) << other.output;
    EXPECT_EQ(other.output.rfind("masse: --set sheet.structure=square2d: " + knife + ": sheet.size: ", 0), 0u)
        << other.output;
    EXPECT_FALSE(std::filesystem::exists(out));
}

// `masse converge`: a request it cannot carry out (fewer than two sizes, sizes out of order, a size too large for
// memory, --size beside --sizes, a scene without a thickness section) gets one message naming what is wrong, exit
// code 2, and nothing written.
TEST(Converge, BadRequestsExitWithCode2AndWriteNothing)
{
    const std::string cup = source + "/data/scenes/vacuum-forming-cup.json";
    const std::pair<std::string, std::string> requests[] = {
        {cup + " --sizes 32", "--sizes: give at least two lattice sizes"},
        {cup + " --sizes 64,32", "--sizes: give the sizes coarsest first: 32x2x32"},
        {cup + " --sizes 16,200000", "--sizes"},
        {cup + " --sizes 16,24 --size 8x2x8", "--size: converge runs the sizes given by --sizes"},
        {source + "/data/scenes/slope.json --sizes 8,12", "the scene needs a material and report.thickness_section"},
    };
    int i = 0;
    for (const auto& [arguments, expected] : requests)
    {
        const std::filesystem::path out = freshFolder("converge-bad-" + std::to_string(++i));
        const Outcome o = runMasse("converge " + arguments + " --quiet --out " + out.string());
        EXPECT_EQ(o.exitCode, 2) << arguments << ":\n" << o.output;
        EXPECT_EQ(o.output.rfind("masse: ", 0), 0u) << o.output;
        EXPECT_NE(o.output.find(expected), std::string::npos) << arguments << ":\n" << o.output;
        EXPECT_FALSE(std::filesystem::exists(out)) << arguments;
    }
}

// A small convergence run: each size's own run in its folder, the comparison's JSON with one difference per pair of
// sizes, the section CSV with a column per size and the band map, all of it finite.
TEST(Converge, WritesEachSizesRunAndTheComparison)
{
    const std::filesystem::path out = freshFolder("converge-cup");
    const Outcome o = runMasse("converge " + source + "/data/scenes/vacuum-forming-cup.json --sizes 8,12,16 " +
                               "--duration 0.3 --threads 1 --quiet --out " + out.string());
    ASSERT_EQ(o.exitCode, 0) << o.output;
    for (const char* size : {"8x2x8", "12x2x12", "16x2x16"})
    {
        EXPECT_TRUE(std::filesystem::exists(out / size / "summary.json")) << size;
    }
    std::ifstream in(out / "convergence.json");
    const nlohmann::json summary = nlohmann::json::parse(in);
    ASSERT_EQ(summary["sizes"].size(), 3u);
    ASSERT_EQ(summary["differences"].size(), 2u);
    for (const nlohmann::json& difference : summary["differences"])
    {
        EXPECT_TRUE(std::isfinite(difference["section_mean"].get<double>()));
        EXPECT_GE(difference["section_largest"].get<double>(), difference["section_mean"].get<double>());
    }
    EXPECT_TRUE(std::isfinite(summary["thinnest"]["estimate_ratio"].get<double>()));
    EXPECT_GE(summary["thinnest"]["band_ratio"].get<double>(), 0);
    std::ifstream csv(out / "convergence_section.csv");
    std::string header;
    std::getline(csv, header);
    EXPECT_EQ(header, "coordinate_m,ratio_8x2x8,ratio_12x2x12,ratio_16x2x16,estimate,band");
    EXPECT_TRUE(std::filesystem::exists(out / "convergence_section.png"));
    // The band map of the finest run's bottom layer: its figures in the JSON, its picture beside it.
    const double largest = summary["map"]["largest_band_ratio"].get<double>();
    const double mean = summary["map"]["mean_band_ratio"].get<double>();
    EXPECT_TRUE(std::isfinite(largest));
    EXPECT_GT(largest, 0) << "the sheet was not drawn in, or the band map compares a run with itself";
    EXPECT_GE(largest, mean);
    EXPECT_GE(mean, 0);
    EXPECT_TRUE(std::filesystem::exists(out / "convergence_map.png"));
}
