// The output folder model (issue 51): MaSSE deletes only what it wrote. Leftovers of killed runs are recognised by a
// name no user would choose, a process that has exited and, for folders, MaSSE's marker inside; runs into one folder
// take a lock.

#include "support/TempFolder.h"
#include "support/TestSystems.h"

#include "scene/output/AtomicFile.h"
#include "scene/output/OutputFolder.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

using namespace masse::scene;
using masse::test::inputErrorOf;
namespace fs = std::filesystem;

namespace
{
fs::path freshFolder(const std::string& name)
{
    return masse::test::freshTempFolder("output-folder-" + name);
}

void writeText(const fs::path& path, const std::string& text)
{
    std::ofstream out(path, std::ios::binary);
    out << text;
}

std::string readText(const fs::path& path)
{
    std::ifstream in(path);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

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
} // namespace

// Of the entries beside a run's folder named like its leftovers ("*.tmp-N", ".*.partial-N", ".*.old-N", N not a running
// process), only MaSSE's own forms are removed, and a folder only with MaSSE's marker inside (or empty); a user's
// entry that merely looks like one stays.
TEST(OutputFolder, OnlyLeftoversInMassesOwnFormAreRemoved)
{
    const fs::path folder = freshFolder("leftovers");
    const std::string dead = deadProcess();
    const std::string live = std::to_string(::getpid());
    // A user's names, the old patterns: all stay.
    fs::create_directories(folder / ("thesis.tmp-" + dead));
    writeText(folder / ("thesis.tmp-" + dead) / "thesis.tex", "thesis");
    writeText(folder / ("notes.tmp-" + dead), "notes");
    writeText(folder / (".x.partial-" + dead), "x");
    fs::create_directories(folder / (".run.old-" + dead));
    writeText(folder / (".run.old-" + dead) / "old.txt", "old");
    // MaSSE's forms without the marker: a folder a user filled stays; an empty one (killed before its marker) goes.
    fs::create_directories(folder / (".mine.masse-partial-" + dead + "-0123abcd"));
    writeText(folder / (".mine.masse-partial-" + dead + "-0123abcd") / "mine.txt", "mine");
    fs::create_directories(folder / (".empty.masse-partial-" + dead + "-0123abcd"));
    // MaSSE's forms with the marker, of a process that exited: removed; of a live one: kept.
    fs::create_directories(folder / (".run.masse-partial-" + dead + "-89abcdef"));
    writeText(folder / (".run.masse-partial-" + dead + "-89abcdef") / ".masse-manifest.json", "{}");
    writeText(folder / (".run.masse-partial-" + dead + "-89abcdef") / "frame_000000.vtp", "half");
    fs::create_directories(folder / (".run.masse-partial-" + live + "-89abcdef"));
    writeText(folder / (".run.masse-partial-" + live + "-89abcdef") / ".masse-manifest.json", "{}");
    writeText(folder / ("summary.json.masse-tmp-" + dead), "half");
    writeText(folder / ("events.csv.masse-tmp-" + live), "ours, still running");
    writeText(folder / ("notes.masse-tmp-" + dead + "x"), "not our form");
    {
        OutputFolder out((folder / "run").string(), false);
    }
    EXPECT_EQ(readText(folder / ("thesis.tmp-" + dead) / "thesis.tex"), "thesis");
    EXPECT_EQ(readText(folder / ("notes.tmp-" + dead)), "notes");
    EXPECT_EQ(readText(folder / (".x.partial-" + dead)), "x");
    EXPECT_EQ(readText(folder / (".run.old-" + dead) / "old.txt"), "old");
    EXPECT_EQ(readText(folder / (".mine.masse-partial-" + dead + "-0123abcd") / "mine.txt"), "mine");
    EXPECT_FALSE(fs::exists(folder / (".empty.masse-partial-" + dead + "-0123abcd")));
    EXPECT_FALSE(fs::exists(folder / (".run.masse-partial-" + dead + "-89abcdef")));
    EXPECT_TRUE(fs::exists(folder / (".run.masse-partial-" + live + "-89abcdef")));
    EXPECT_FALSE(fs::exists(folder / ("summary.json.masse-tmp-" + dead)));
    EXPECT_TRUE(fs::exists(folder / ("events.csv.masse-tmp-" + live)));
    EXPECT_EQ(readText(folder / ("notes.masse-tmp-" + dead + "x")), "not our form");

    // The first atomic write into a folder tidies it the same way.
    const fs::path single = freshFolder("leftover-file");
    writeText(single / ("expected.json.masse-tmp-" + dead), "half");
    writeText(single / ("expected.json.tmp-" + dead), "a user's");
    writeFileAtomically((single / "expected.json").string(), "{}\n");
    EXPECT_FALSE(fs::exists(single / ("expected.json.masse-tmp-" + dead)));
    EXPECT_EQ(readText(single / ("expected.json.tmp-" + dead)), "a user's");
}

// A forced replacement killed between its two renames (the earlier result in the old-folder, the new one in
// the staging folder, nothing under the folder's own name) is undone by the next run into the folder: the earlier
// result is back, and the new run then replaces it (with force) or refuses (without).
TEST(OutputFolder, AReplacementKilledBetweenItsRenamesIsUndone)
{
    const fs::path folder = freshFolder("interrupted");
    const std::string target = (folder / "run").string();
    {
        OutputFolder first(target, false);
        writeText(fs::path(first.staging()) / "summary.json", "first");
        first.commit();
    }
    ASSERT_TRUE(fs::exists(folder / "run" / ".masse-manifest.json")) << "no manifest in the output folder";
    const std::string dead = deadProcess();
    const fs::path old = folder / (".run.masse-old-" + dead + "-0123abcd");
    const fs::path partial = folder / (".run.masse-partial-" + dead + "-89abcdef");
    fs::rename(folder / "run", old);
    fs::create_directories(partial);
    fs::copy_file(old / ".masse-manifest.json", partial / ".masse-manifest.json");
    writeText(partial / "summary.json", "second, never committed");

    EXPECT_NE(inputErrorOf([&] { OutputFolder again(target, false); }).find("already holds a run (summary.json)"),
              std::string::npos);
    EXPECT_EQ(readText(folder / "run" / "summary.json"), "first");
    EXPECT_FALSE(fs::exists(old));
    EXPECT_FALSE(fs::exists(partial));
    {
        OutputFolder forced(target, true);
        writeText(fs::path(forced.staging()) / "summary.json", "third");
        forced.commit();
    }
    EXPECT_EQ(readText(folder / "run" / "summary.json"), "third");
    std::size_t entries = 0;
    for ([[maybe_unused]] const auto& entry : fs::directory_iterator(folder))
    {
        ++entries;
    }
    EXPECT_EQ(entries, 1u) << "a staging folder, an old folder or a lock file was left beside the output";
}

// A second run into a folder another is writing is refused at once (InputError: exit code 2), and once the
// first has finished the folder is free again.
TEST(OutputFolder, ASecondRunIntoTheSameFolderIsRefusedWhileTheFirstWrites)
{
    const fs::path folder = freshFolder("locked");
    const std::string target = (folder / "run").string();
    {
        OutputFolder first(target, false);
        writeText(fs::path(first.staging()) / "summary.json", "first");
        const std::string message = inputErrorOf([&] { OutputFolder second(target, true); });
        EXPECT_NE(message.find("another masse run is writing"), std::string::npos) << message;
        EXPECT_NE(message.find(target), std::string::npos) << message;
        first.commit();
    }
    EXPECT_EQ(readText(folder / "run" / "summary.json"), "first");
    {
        OutputFolder later(target, true);
        writeText(fs::path(later.staging()) / "summary.json", "later");
        later.commit();
    }
    EXPECT_EQ(readText(folder / "run" / "summary.json"), "later");
}

// What a user put into an output folder during the run is not replaced with it: the run fails at its commit
// (exit code 1), and the folder keeps the earlier result and the user's file.
TEST(OutputFolder, AFileAddedDuringTheRunIsNotReplaced)
{
    const fs::path folder = freshFolder("added");
    const std::string target = (folder / "run").string();
    {
        OutputFolder first(target, false);
        writeText(fs::path(first.staging()) / "summary.json", "first");
        first.commit();
    }
    {
        OutputFolder forced(target, true);
        writeText(fs::path(forced.staging()) / "summary.json", "second");
        writeText(folder / "run" / "notes.txt", "written while the run went on");
        try
        {
            forced.commit();
            ADD_FAILURE() << "the commit replaced a folder holding the user's notes.txt";
        }
        catch (const std::runtime_error& e)
        {
            EXPECT_NE(std::string(e.what()).find("notes.txt"), std::string::npos) << e.what();
        }
    }
    EXPECT_EQ(readText(folder / "run" / "summary.json"), "first");
    EXPECT_EQ(readText(folder / "run" / "notes.txt"), "written while the run went on");
}

// A manifest names paths inside its folder only: one that lists "../notes.txt" (damaged, or written by hand) makes
// no run or study remove a file outside it.
TEST(OutputFolder, AManifestReachesNothingOutsideItsFolder)
{
    const fs::path folder = freshFolder("outside");
    fs::create_directories(folder / "case");
    writeText(folder / "notes.txt", "mine");
    writeText(folder / "case" / ".masse-manifest.json",
              R"({"written": ["../notes.txt", "/etc/hostname"], "kept": ["scene.json", ".."]})");
    removeListedOutputs((folder / "case").string(), {});
    EXPECT_EQ(readText(folder / "notes.txt"), "mine");
    EXPECT_TRUE(fs::exists("/etc/hostname"));
}
