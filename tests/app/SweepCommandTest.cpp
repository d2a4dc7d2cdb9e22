// `masse sweep` as a user meets it: --set on the run command, a small study run with one and two workers, a sweep
// killed mid-way and resumed, and bad studies refused before anything runs.

#include "support/MasseCommand.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <array>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/stat.h>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

namespace
{
namespace fs = std::filesystem;

const std::string source = MASSE_SOURCE_DIR;
const std::string study = source + "/tests/studies/slope-friction.json";
constexpr std::size_t caseCount = 8;

fs::path freshFolder(const std::string& name)
{
    const fs::path folder = fs::path(testing::TempDir()) / name;
    fs::remove_all(folder);
    return folder;
}

std::string readText(const fs::path& path)
{
    std::ifstream in(path);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

std::string caseName(std::size_t i)
{
    char name[16];
    std::snprintf(name, sizeof(name), "%04zu", i);
    return name;
}

std::size_t finishedCases(const fs::path& dir)
{
    std::size_t count = 0;
    for (std::size_t i = 0; i < caseCount; ++i)
    {
        count += fs::exists(dir / "cases" / caseName(i) / "status.txt") ? 1 : 0;
    }
    return count;
}

/// The results of a clean run with one worker, for the tests that compare with it (in a folder of the test's own:
/// ctest runs tests in parallel processes).
std::string referenceResults()
{
    const fs::path dir =
        freshFolder(std::string("sweep-reference-") + testing::UnitTest::GetInstance()->current_test_info()->name());
    const Outcome o = runMasse("sweep " + study + " --out " + dir.string() + " --jobs 1 --no-plots");
    EXPECT_EQ(o.exitCode, 0) << o.output;
    return readText(dir / "results.csv");
}
} // namespace

TEST(SetOption, RunTakesSetAndRefusesAnUnknownKeyWithCode2)
{
    const fs::path dir = freshFolder("set-run");
    const Outcome ok = runMasse("run " + source + "/data/scenes/slope.json --set contact.friction=0.2 --set " +
                                "run.duration=0.3 --quiet --out " + dir.string());
    ASSERT_EQ(ok.exitCode, 0) << ok.output;
    const nlohmann::json summary = nlohmann::json::parse(readText(dir / "summary.json"));
    EXPECT_NEAR(summary["sim_seconds"].get<double>(), 0.3, 0.011); // the duration set, to a step

    const fs::path bad = freshFolder("set-run-bad");
    const Outcome unknown =
        runMasse("run " + source + "/data/scenes/slope.json --set contact.frction=0.2 --out " + bad.string());
    EXPECT_EQ(unknown.exitCode, 2) << unknown.output;
    EXPECT_NE(unknown.output.find("--set contact.frction=0.2: "), std::string::npos) << unknown.output;
    EXPECT_NE(unknown.output.find("did you mean 'friction'"), std::string::npos) << unknown.output;
    EXPECT_FALSE(fs::exists(bad)) << "nothing is written for bad input";
    const std::vector<std::string> commands = {"check " + source + "/data/regression/slope.json", "view",
                                               "compare " + source + "/data/scenes/slope.json --out " + bad.string()};
    for (const std::string& command : commands)
    {
        const Outcome o = runMasse(command + " --set contact.frction=0.2");
        EXPECT_EQ(o.exitCode, 2) << command << ": " << o.output;
        EXPECT_NE(o.output.find("contact.frction"), std::string::npos) << command << ": " << o.output;
    }
}

TEST(Sweep, TwoWorkersGiveTheSameResultsAsOne)
{
    const std::string one = referenceResults();
    const fs::path dir = freshFolder("sweep-two-jobs");
    const Outcome two = runMasse("sweep " + study + " --out " + dir.string() + " --jobs 2");
    ASSERT_EQ(two.exitCode, 0) << two.output;
    EXPECT_EQ(readText(dir / "results.csv"), one);

    // Every case ran and reached the stopper; the stopper is reached later with more friction, as
    // t = sqrt(2 d / (g (sin 30 - mu cos 30))) says (d = 0.99 m), within 5%.
    std::istringstream rows(one);
    std::string row;
    std::getline(rows, row);
    EXPECT_EQ(row, "case,status,exit_code,friction [1],integrator,stopper contact [s],final.bbox_min[0] [m],"
                   "final.state_hash,message");
    std::size_t count = 0;
    while (std::getline(rows, row))
    {
        std::vector<std::string> cells;
        std::stringstream fields(row);
        for (std::string cell; std::getline(fields, cell, ',');)
        {
            cells.push_back(cell);
        }
        ASSERT_GE(cells.size(), 6u) << row;
        EXPECT_EQ(cells[1], "done") << row;
        const double mu = std::stod(cells[3]);
        const double expected = std::sqrt(2 * 0.99 / (9.80665 * (0.5 - mu * std::sqrt(3.0) / 2)));
        EXPECT_NEAR(std::stod(cells[5]), expected, 0.05 * expected) << row;
        ++count;
    }
    EXPECT_EQ(count, caseCount);
    EXPECT_TRUE(fs::exists(dir / "cases.csv"));
    EXPECT_TRUE(fs::exists(dir / "cases" / "0003" / "scene.json"));
    EXPECT_TRUE(fs::exists(dir / "plots" / "stopper_contact-vs-friction.png"));
    EXPECT_NE(two.output.find("overhead per case"), std::string::npos) << two.output;
}

TEST(Sweep, AKilledSweepResumesWithOnlyTheMissingCases)
{
    const std::string reference = referenceResults();
    const fs::path dir = freshFolder("sweep-killed");
    const fs::path log = fs::path(testing::TempDir()) / "sweep-killed.log";
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0)
    {
        const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        ::dup2(fd, STDOUT_FILENO);
        ::dup2(fd, STDERR_FILENO);
        ::execl(MASSE_EXECUTABLE, MASSE_EXECUTABLE, "sweep", study.c_str(), "--out", dir.c_str(), "--jobs", "1",
                "--no-plots", static_cast<char*>(nullptr));
        ::_exit(127);
    }
    // Kill it (SIGKILL: no chance to tidy up) once two cases have finished.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(120);
    while (finishedCases(dir) < 2 && std::chrono::steady_clock::now() < deadline)
    {
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    ::kill(pid, SIGKILL);
    int status = 0;
    ::waitpid(pid, &status, 0);
    const std::size_t finished = finishedCases(dir);
    ASSERT_GE(finished, 2u) << readText(log);
    ASSERT_LT(finished, caseCount) << "the sweep ended before it was killed: the test needs slower cases";
    std::vector<std::string> earlier;
    for (std::size_t i = 0; i < caseCount; ++i)
    {
        earlier.push_back(readText(dir / "cases" / caseName(i) / "status.txt"));
    }

    std::this_thread::sleep_for(std::chrono::milliseconds(200)); // the killed sweep's worker dies with it
    const Outcome resumed = runMasse("sweep " + study + " --out " + dir.string() + " --jobs 2 --no-plots");
    ASSERT_EQ(resumed.exitCode, 0) << resumed.output;
    EXPECT_NE(resumed.output.find(std::to_string(caseCount - finished) + " to run, " + std::to_string(finished) +
                                  " finished earlier"),
              std::string::npos)
        << resumed.output;
    for (std::size_t i = 0; i < caseCount; ++i)
    {
        if (!earlier[i].empty())
        {
            EXPECT_EQ(readText(dir / "cases" / caseName(i) / "status.txt"), earlier[i]) << "case " << i << " reran";
        }
    }
    EXPECT_EQ(finishedCases(dir), caseCount);
    EXPECT_EQ(readText(dir / "results.csv"), reference);

    // Once more: nothing left to run.
    const Outcome again = runMasse("sweep " + study + " --out " + dir.string() + " --no-plots");
    EXPECT_EQ(again.exitCode, 0) << again.output;
    EXPECT_NE(again.output.find("0 to run, 8 finished earlier"), std::string::npos) << again.output;
}

TEST(Sweep, AFailedCaseIsRecordedAndTheOthersRun)
{
    // Scene files are checked for every case before the study starts; a mesh file is first opened when the case's
    // scene is built, so a missing mesh in the second case makes that case fail when it runs.
    const fs::path folder = freshFolder("sweep-failing-study");
    fs::create_directories(folder);
    const nlohmann::json stopper = nlohmann::json::parse(readText(source + "/data/scenes/slope.json"))["obstacles"][1];
    nlohmann::json missing = {{"name", "stopper"}, {"type", "mesh"}, {"file", "missing.obj"}};
    const nlohmann::json failing = {
        {"scene", source + "/data/scenes/slope.json"},
        {"set", {{"run.duration", 0.2}}},
        {"vary", {{{"name", "stopper"}, {"key", "obstacles[1]"}, {"values", {stopper, missing}}}}},
        {"outputs", {"sim_seconds"}}};
    std::ofstream(folder / "failing.json") << failing.dump(2);
    const fs::path dir = freshFolder("sweep-failing");
    const Outcome o = runMasse("sweep " + (folder / "failing.json").string() + " --out " + dir.string() + " --jobs 2");
    EXPECT_EQ(o.exitCode, 1) << o.output;
    EXPECT_NE(o.output.find("1 case(s) failed"), std::string::npos) << o.output;
    const std::string results = readText(dir / "results.csv");
    EXPECT_NE(results.find("\n0,done,0,"), std::string::npos) << results;
    EXPECT_NE(results.find("\n1,failed,2,"), std::string::npos) << results;
    EXPECT_NE(results.find("missing.obj"), std::string::npos) << results;

    // --collect writes the same results and names the failed case, its folder and why, and exits 1 as the sweep
    // does: a study with a failed case is a run that went wrong.
    fs::remove(dir / "results.csv");
    const Outcome collected = runMasse("sweep --collect " + dir.string() + " --no-plots");
    EXPECT_EQ(collected.exitCode, 1) << collected.output;
    EXPECT_EQ(readText(dir / "results.csv"), results);
    const std::string named = "case 0001 failed (exit code 2) in " + (dir / "cases" / "0001").string() + ": ";
    const std::size_t at = collected.output.find(named);
    ASSERT_NE(at, std::string::npos) << collected.output;
    EXPECT_NE(collected.output.find("missing.obj", at), std::string::npos) << collected.output;
    EXPECT_EQ(collected.output.find("case 0000 failed"), std::string::npos) << collected.output;
    EXPECT_NE(collected.output.find("1 case(s) failed; results.csv says why"), std::string::npos) << collected.output;

    // So does a --slurm sweep of the finished study, which has nothing to submit and only collects.
    const Outcome slurm =
        runMasse("sweep " + (folder / "failing.json").string() + " --out " + dir.string() + " --slurm --no-plots");
    EXPECT_EQ(slurm.exitCode, 1) << slurm.output;
    EXPECT_NE(slurm.output.find(named), std::string::npos) << slurm.output;
}

TEST(Sweep, BadStudiesExitWithCode2AndWriteNothing)
{
    const fs::path folder = freshFolder("sweep-bad-studies");
    fs::create_directories(folder);
    const std::string scene = source + "/data/scenes/slope.json";
    const std::vector<std::pair<std::string, std::string>> studies = {
        {R"([{"key": "contact.frction", "values": [0.1, 0.2]}])", "vary[0]: contact.frction=0.1"},
        {R"([{"key": "contact.friction", "range": {"min": 0.1, "max": 0.3, "count": 0}}])",
         "vary[0].range.count: empty range"},
        {R"([{"key": "contact.friction", "values": [0.1, -0.5]}])", "case 1 (contact.friction=-0.5)"},
    };
    for (std::size_t i = 0; i < studies.size(); ++i)
    {
        const fs::path path = folder / ("bad-" + std::to_string(i) + ".json");
        std::ofstream(path) << "{ \"scene\": \"" << scene << "\", \"vary\": " << studies[i].first
                            << ", \"outputs\": [\"sim_seconds\"] }";
        const fs::path dir = folder / ("out-" + std::to_string(i));
        const Outcome o = runMasse("sweep " + path.string() + " --out " + dir.string());
        EXPECT_EQ(o.exitCode, 2) << o.output;
        EXPECT_NE(o.output.find(studies[i].second), std::string::npos) << o.output;
        EXPECT_FALSE(fs::exists(dir)) << "nothing written for a bad study";
    }
    const Outcome notStudy = runMasse("sweep --collect " + folder.string());
    EXPECT_EQ(notStudy.exitCode, 2) << notStudy.output;
}

// The sweep runs each case in a forked copy of itself (no new program load): a case must come out exactly as `masse
// run` of its scene file in a fresh process does, state hash and all.
TEST(Sweep, ACaseRunsAsMasseRunWouldInAFreshProcess)
{
    const fs::path dir = freshFolder("sweep-in-process");
    const Outcome sweep = runMasse("sweep " + study + " --out " + dir.string() + " --jobs 1 --no-plots");
    ASSERT_EQ(sweep.exitCode, 0) << sweep.output;
    const fs::path caseDir = dir / "cases" / "0005";
    const fs::path alone = freshFolder("sweep-in-process-alone");
    const Outcome run =
        runMasse("run " + (caseDir / "scene.json").string() + " --out " + alone.string() + " --quiet --threads 1");
    ASSERT_EQ(run.exitCode, 0) << run.output;
    const nlohmann::json inSweep = nlohmann::json::parse(readText(caseDir / "summary.json"));
    const nlohmann::json inFreshProcess = nlohmann::json::parse(readText(alone / "summary.json"));
    ASSERT_TRUE(inSweep["final"].contains("state_hash")) << inSweep.dump();
    EXPECT_EQ(inSweep["final"]["state_hash"], inFreshProcess["final"]["state_hash"]);
    EXPECT_EQ(inSweep["final"]["kinetic_energy"], inFreshProcess["final"]["kinetic_energy"]);
    ASSERT_EQ(inSweep["events"].size(), inFreshProcess["events"].size());
    ASSERT_FALSE(inSweep["events"].empty());
    for (std::size_t e = 0; e < inSweep["events"].size(); ++e)
    {
        EXPECT_EQ(inSweep["events"][e]["name"], inFreshProcess["events"][e]["name"]);
        EXPECT_EQ(inSweep["events"][e]["sim_time"], inFreshProcess["events"][e]["sim_time"]);
    }
}

// A thread count masse run refuses (--threads 100000) is refused before anything is written; otherwise the study folder
// would hold cases that all failed, and a later good sweep would skip them as finished.
TEST(Sweep, AThreadCountMasseRunRefusesIsRefusedBeforeAnythingIsWritten)
{
    const fs::path dir = freshFolder("sweep-threads");
    for (const std::string threads : {"100000", "0", "''"})
    {
        const Outcome o = runMasse("sweep " + study + " --out " + dir.string() + " --threads " + threads);
        EXPECT_EQ(o.exitCode, 2) << o.output;
        EXPECT_NE(o.output.find("--threads: must be a whole number of threads from 1 to 1024"), std::string::npos)
            << o.output;
        EXPECT_FALSE(fs::exists(dir)) << threads;
    }
}

// A case whose summary.json is a pipe, or whose events are not objects, fails on its own, rather than blocking
// --collect for ever or stopping the whole collection with the JSON library's message; results.csv holds the others. A
// study name with a newline, which would break the plots after every case had run, is refused when the study is read.
TEST(Sweep, BrokenSummariesFailTheirOwnCaseAndANameMustBeOneLine)
{
    const fs::path folder = freshFolder("sweep-broken-summaries");
    fs::create_directories(folder);
    const nlohmann::json design = {{"scene", source + "/data/scenes/slope.json"},
                                   {"set", {{"run.duration", 0.2}}},
                                   {"vary", {{{"key", "contact.friction"}, {"values", {0.1, 0.2, 0.3}}}}},
                                   {"outputs", {"sim_seconds", "event:contact:slope"}}};
    nlohmann::json named = design;
    named["name"] = "two\nlines";
    std::ofstream(folder / "named.json") << named.dump(2);
    const Outcome refused =
        runMasse("sweep " + (folder / "named.json").string() + " --out " + (folder / "named").string());
    EXPECT_EQ(refused.exitCode, 2) << refused.output;
    EXPECT_NE(refused.output.find("name: must be one line without control characters"), std::string::npos)
        << refused.output;
    EXPECT_FALSE(fs::exists(folder / "named"));

    std::ofstream(folder / "design.json") << design.dump(2);
    const fs::path dir = folder / "study";
    const Outcome ran =
        runMasse("sweep " + (folder / "design.json").string() + " --out " + dir.string() + " --no-plots");
    ASSERT_EQ(ran.exitCode, 0) << ran.output;
    fs::remove(dir / "cases" / "0000" / "summary.json");
    ASSERT_EQ(::mkfifo((dir / "cases" / "0000" / "summary.json").c_str(), 0600), 0);
    nlohmann::json summary = nlohmann::json::parse(readText(dir / "cases" / "0001" / "summary.json"));
    summary["events"] = {1, 2};
    std::ofstream(dir / "cases" / "0001" / "summary.json") << summary.dump();
    const Outcome collected = runMasse("sweep --collect " + dir.string() + " --no-plots");
    // The collection goes on past the broken cases, names them and exits 1: their runs went wrong.
    EXPECT_EQ(collected.exitCode, 1) << collected.output;
    EXPECT_NE(collected.output.find("case 0000 failed (exit code 0) in " + (dir / "cases" / "0000").string() +
                                    ": exit code 0 but no readable summary.json"),
              std::string::npos)
        << collected.output;
    EXPECT_NE(collected.output.find("case 0001 failed (exit code 0) in "), std::string::npos) << collected.output;
    EXPECT_NE(collected.output.find("2 case(s) failed"), std::string::npos) << collected.output;
    const std::string results = readText(dir / "results.csv");
    EXPECT_NE(results.find("\n0,failed,0,"), std::string::npos) << results;
    EXPECT_NE(results.find("no readable summary.json"), std::string::npos) << results;
    EXPECT_NE(results.find("\n1,failed,0,"), std::string::npos) << results;
    EXPECT_NE(results.find("summary.json: events[0] is not an event as masse run writes it"), std::string::npos)
        << results;
    EXPECT_NE(results.find("\n2,done,0,"), std::string::npos) << results;
}

// A study record whose cases do not match its parameters (edited by hand, or cut short) is refused with the case
// named, before anything is written: the tables index a case's values by parameter.
TEST(Sweep, ARecordWhoseCasesDoNotMatchItsParametersIsRefused)
{
    const fs::path dir = freshFolder("sweep-mismatched-record");
    const Outcome ran = runMasse("sweep " + study + " --out " + dir.string() + " --no-plots");
    ASSERT_EQ(ran.exitCode, 0) << ran.output;
    fs::remove(dir / "results.csv");
    nlohmann::json record = nlohmann::json::parse(readText(dir / "study.json"));
    ASSERT_EQ(record["parameters"].size(), 2u);
    record["parameters"].erase(1);
    std::ofstream(dir / "study.json") << record.dump(2);
    const Outcome collected = runMasse("sweep --collect " + dir.string() + " --no-plots");
    EXPECT_EQ(collected.exitCode, 2) << collected.output;
    EXPECT_NE(collected.output.find("cases[0] has 2 value(s) for 1 parameter(s)"), std::string::npos)
        << collected.output;
    EXPECT_FALSE(fs::exists(dir / "results.csv"));
}

// --slurm where sbatch is installed but no cluster answers says that no cluster answers and what to do, rather than
// printing sbatch's raw DNS errors. (An sbatch of the test's own stands in for the installed one.)
TEST(Sweep, SlurmWithoutAClusterSaysWhatToDo)
{
    const fs::path folder = freshFolder("sweep-no-cluster");
    fs::create_directories(folder / "bin");
    std::ofstream(folder / "bin" / "sbatch")
        << "#!/bin/sh\n"
           "echo 'sbatch: error: resolve_ctls_from_dns_srv: res_nsearch error: Unknown host'\n"
           "echo 'sbatch: error: fetch_config: DNS SRV lookup failed'\n"
           "echo 'sbatch: fatal: Could not establish a configuration source'\n"
           "exit 1\n";
    fs::permissions(folder / "bin" / "sbatch", fs::perms::owner_all);
    const std::string command = "PATH='" + (folder / "bin").string() + "':\"$PATH\" " + std::string(MASSE_EXECUTABLE) +
                                " sweep " + study + " --out " + (folder / "study").string() + " --slurm 2>&1";
    FILE* pipe = ::popen(command.c_str(), "r");
    ASSERT_NE(pipe, nullptr);
    std::string output;
    std::array<char, 512> buffer{};
    while (std::fgets(buffer.data(), int(buffer.size()), pipe))
    {
        output += buffer.data();
    }
    const int status = ::pclose(pipe);
    EXPECT_EQ(WEXITSTATUS(status), 1) << output;
    EXPECT_NE(output.find("no Slurm cluster answers this machine's sbatch (sbatch: fatal: Could not establish a "
                          "configuration source): configure Slurm here"),
              std::string::npos)
        << output;
    EXPECT_NE(output.find("or run the cases on this machine with --jobs N instead of --slurm"), std::string::npos)
        << output;
}
