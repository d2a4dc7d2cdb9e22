// Hostile and careless input (issue 16): every file in tests/bad-scenes/ and tests/data/ that once crashed, was read
// wrongly or was refused too late is refused at once with one message naming the file and the key or line; files too
// large to keep in the repository (deep nesting, a mesh past Bullet's triangle limit) are made here at run time.

#include "support/GuardedRun.h"
#include "support/TestSystems.h"

#include "bridge/MeshFile.h"
#include "bridge/StlFile.h"
#include "core/NumericalError.h"
#include "scene/MemoryBudget.h"
#include "scene/Runner.h"
#include "scene/Scene.h"
#include "scene/SceneFile.h"
#include "scene/SceneOverrides.h"
#include "scene/json/JsonObject.h"
#include "scene/output/AtomicFile.h"
#include "scene/output/FiniteOutput.h"
#include "scene/output/OutputFolder.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

using namespace masse;
using namespace masse::scene;
using masse::test::inputErrorOf;

namespace
{
const std::string source = MASSE_SOURCE_DIR;
const std::string badScenes = source + "/tests/bad-scenes/";

std::string buildError(const std::string& file)
{
    return inputErrorOf([&] { Scene scene(loadScene(file)); });
}

std::filesystem::path freshFolder(const std::string& name)
{
    const std::filesystem::path folder = std::filesystem::path(testing::TempDir()) / ("hostile-" + name);
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder);
    return folder;
}

void writeText(const std::filesystem::path& path, const std::string& text)
{
    std::ofstream out(path, std::ios::binary);
    out << text;
}

/// The id of a process that has exited (forked, reaped): what a run killed with -9 leaves in its temporary names.
pid_t deadProcess()
{
    const pid_t child = ::fork();
    if (child == 0)
    {
        ::_exit(0);
    }
    int status = 0;
    ::waitpid(child, &status, 0);
    return child;
}
} // namespace

// 120 KB of "[" is refused as bad input without overflowing the stack (the error message does not dump the document
// recursively).
TEST(HostileInput, DeeplyNestedJsonIsRefusedWithTheDepth)
{
    const std::filesystem::path folder = freshFolder("deep");
    writeText(folder / "deep.json", std::string(120000, '['));
    const std::string message = inputErrorOf([&] { loadScene((folder / "deep.json").string()); });
    EXPECT_NE(message.find("deep.json: "), std::string::npos) << message;
    EXPECT_NE(message.find("nested deeper than 64 levels"), std::string::npos) << message;

    writeText(folder / "deep-material.json", "{\"forming_window\": " + std::string(60000, '[') + "}");
    const std::string material = inputErrorOf([&] { readJsonFile((folder / "deep-material.json").string()); });
    EXPECT_NE(material.find("deep-material.json: forming_window"), std::string::npos) << material;
}

// A number beyond double range is bad input (exit 2) naming the file and the key, in a scene, the base it
// extends, or its material file.
TEST(HostileInput, NumbersBeyondDoubleRangeNameFileAndKey)
{
    const std::string scene = buildError(badScenes + "number-overflow.json");
    EXPECT_NE(scene.find("number-overflow.json: sheet.mass: number overflow parsing '1e400'"), std::string::npos)
        << scene;
    const std::string base = buildError(badScenes + "extends-overflow.json");
    EXPECT_NE(base.find("number-overflow.json: sheet.mass: number overflow"), std::string::npos) << base;
    const std::string material = buildError(badScenes + "material-overflow.json");
    EXPECT_NE(material.find("overflow-material.json: density: number overflow parsing '1e400'"), std::string::npos)
        << material;
}

// A folder where a scene, base or material file should be is named, not read as an empty file.
TEST(HostileInput, AFolderForAFileIsRefusedByName)
{
    const std::filesystem::path folder = freshFolder("folder-scene");
    std::filesystem::create_directories(folder / "scene.json");
    const std::string message = buildError((folder / "scene.json").string());
    EXPECT_NE(message.find("scene.json: is a folder, not a JSON file"), std::string::npos) << message;
}

// A scene file name that is not UTF-8 is handled before the run: it would make summary.json unwritable at its end.
TEST(HostileInput, ASceneFileNameThatIsNotUtf8IsRefusedUpFront)
{
    const std::filesystem::path folder = freshFolder("utf8");
    const std::string name = (folder / "sc\xE9ne.json").string();
    writeText(name, "{}");
    const std::string message = buildError(name);
    EXPECT_NE(message.find("sc\\xE9ne.json: the file name is not valid UTF-8"), std::string::npos) << message;
}

// A pinned mass index beyond the index type is refused with the index and the range, rather than cast from a double
// (undefined behaviour, which would pin mass 1 or 0).
TEST(HostileInput, PinnedMassesBeyondTheIndexRangeAreRefused)
{
    const std::string past = buildError(badScenes + "pin-past-index-range.json");
    EXPECT_NE(past.find("sheet.pinned.masses: expected mass indices, whole numbers in [0, 4294967294] (got "
                        "4294967297)"),
              std::string::npos)
        << past;
    const std::string huge = buildError(badScenes + "pin-huge.json");
    EXPECT_NE(huge.find("(got 1e+300)"), std::string::npos) << huge;
}

// Values that make a run that never ends or flings the sheet are refused by range, naming the key.
TEST(HostileInput, AbsurdValuesAreRefusedByRange)
{
    const std::pair<const char*, const char*> cases[] = {
        {"dt-tiny.json", "integrator.dt: must be in [1e-06, 1] (got 1e-308)"},
        {"duration-huge.json", "run.duration: must be in (0, 1e+06] s (got 1e+300)"},
        {"contact-radius-huge.json", "contact.radius: must be in (0, 0.1] m (got 1e+06)"},
        {"repulsion-huge.json", "sheet.repulsion: must be in [0, 1] (got 1000)"},
        {"stiffness-huge.json", "sheet.stiffness.planar: must be in (0, 1e+06] N/m (got 1e+12)"},
        {"mass-tiny.json", "sheet.mass: must be in [1e-06, 1000] (got 1e-12)"},
    };
    for (const auto& [file, expected] : cases)
    {
        const std::string message = buildError(badScenes + file);
        EXPECT_NE(message.find(badScenes + file + ": " + expected), std::string::npos) << file << ": " << message;
    }
}

// A step the explicit integrator cannot take is found when the scene is built, not at its first step (after the output
// folder and the first frame are written); the message's numbers are readable.
TEST(HostileInput, AStepTooLargeIsRefusedWhenTheSceneIsBuilt)
{
    const std::string message = buildError(badScenes + "stiff-explicit-step.json");
    EXPECT_NE(message.find("integrator.dt: the symplectic integrator needs"), std::string::npos) << message;
    EXPECT_EQ(message.find("0.000000"), std::string::npos) << message;
    EXPECT_EQ(message.find("-9223372036854775808"), std::string::npos) << message;
}

// tinyobjloader reads "nan" and "inf" as 0, and casts a vw line's vertex number to int unchecked: both are refused
// naming the file and the line.
TEST(HostileInput, ObjVerticesThatAreNotFiniteNumbersNameTheLine)
{
    const std::string nan = buildError(badScenes + "mesh-nan-vertex.json");
    EXPECT_NE(nan.find("nan-vertex.obj', line 4: vertex coordinate 'nan' is not a finite number"), std::string::npos)
        << nan;
    const std::string inf = buildError(badScenes + "mesh-inf-vertex.json");
    EXPECT_NE(inf.find("inf-vertex.obj', line 3: vertex coordinate 'inf' is not a finite number"), std::string::npos)
        << inf;
    const std::string weight = buildError(badScenes + "mesh-vertex-weight.json");
    EXPECT_NE(weight.find("vertex-weight-huge.obj', line 5: a vertex weight (vw) needs a vertex number"),
              std::string::npos)
        << weight;
}

// An OBJ face of one or two vertices, which tinyobjloader would drop without a word, and a mesh file that is a symbolic
// link to itself are both refused naming the obstacle and the file (and the line of the face), rather than the face
// vanishing or the run ending in a raw filesystem error.
TEST(HostileInput, ObjFacesOfFewerThanThreeVerticesAndLinkLoopsAreNamed)
{
    const std::filesystem::path folder = freshFolder("short-faces");
    for (const std::string face : {"f 1", "f 1 2"})
    {
        writeText(folder / "short.obj", "v 0 0 0\nv 1 0 0\nv 0 0 1\nv 0 1 0\nf 1 2 3\n" + face + "\nf 1 3 4\n");
        const std::string message = inputErrorOf([&] { bridge::loadMeshFile((folder / "short.obj").string(), "cup"); });
        EXPECT_NE(message.find("obstacle 'cup': mesh file '" + (folder / "short.obj").string() +
                               "', line 6: a face needs at least 3 vertices (got " + std::to_string(face.size() / 2) +
                               ")"),
                  std::string::npos)
            << message;
    }
    std::filesystem::create_symlink("loop.obj", folder / "loop.obj");
    const std::string loop = inputErrorOf([&] { bridge::loadMeshFile((folder / "loop.obj").string(), "cup"); });
    EXPECT_EQ(loop, "obstacle 'cup': mesh file '" + (folder / "loop.obj").string() +
                        "' is a symbolic link that leads back to itself (a loop): link it to the mesh file");
}

// A chain of "extends" is as long as its files, so a valid chain of 11 files is followed, not refused as "too many
// levels (a loop?)"; a loop is found by the files it visits; and a missing base names the file and key that refer to
// it, not the missing file alone.
TEST(HostileInput, ExtendsChainsAreFollowedAndLoopsAndMissingBasesNamed)
{
    const std::filesystem::path folder = freshFolder("extends-chain");
    writeText(folder / "scene-0.json", R"({ "sheet": { "size": "4x2x4" }, "run": { "duration": 0.1 } })");
    for (int i = 1; i <= 11; ++i)
    {
        writeText(folder / ("scene-" + std::to_string(i) + ".json"), R"({ "extends": "scene-)" + std::to_string(i - 1) +
                                                                         R"(.json", "name": "level )" +
                                                                         std::to_string(i) + R"(" })");
    }
    const SceneSpec spec = loadScene((folder / "scene-11.json").string());
    EXPECT_EQ(spec.name, "level 11");
    EXPECT_EQ(spec.sheet.lattice.countX, 4);

    writeText(folder / "a.json", R"({ "extends": "b.json" })");
    writeText(folder / "b.json", R"({ "extends": "a.json" })");
    const std::string loop = inputErrorOf([&] { loadScene((folder / "a.json").string()); });
    EXPECT_NE(loop.find("b.json: extends: 'a.json' leads back to a file of the chain (a loop: "), std::string::npos)
        << loop;

    writeText(folder / "orphan.json", R"({ "extends": "missing.json" })");
    const std::string missing = inputErrorOf([&] { loadScene((folder / "orphan.json").string()); });
    EXPECT_EQ(missing.rfind((folder / "orphan.json").string() + ": extends: the base scene 'missing.json' does not "
                                                                "exist",
                            0),
              0u)
        << missing;
}

// Past 2^21 triangles Bullet's BVH indexes other memory (a SIGSEGV when the sheet nears such a triangle): the mesh is
// refused at the face that goes past the limit.
TEST(HostileInput, AMeshPastBulletsTriangleLimitIsRefused)
{
    const std::filesystem::path folder = freshFolder("huge-mesh");
    {
        std::ofstream out(folder / "huge.obj");
        out << "v 0 0 0\nv 1 0 0\nv 0 0 1\n";
        const std::string face = "f 1 2 3\n";
        std::string block;
        for (int i = 0; i < 4096; ++i)
        {
            block += face;
        }
        for (std::size_t written = 0; written <= bridge::maxMeshTriangles; written += 4096)
        {
            out << block;
        }
    }
    const std::string message = inputErrorOf([&] { bridge::loadObj((folder / "huge.obj").string(), "huge"); });
    EXPECT_NE(message.find("line " + std::to_string(3 + bridge::maxMeshTriangles + 1) + ": more than 2097152"),
              std::string::npos)
        << message;
}

// A sheet inside the documented size range that cannot fit in memory is refused at once, rather than allocating for
// minutes and ending in std::bad_alloc; reading its scene counts its masses without building the lattice.
TEST(HostileInput, ASheetThatCannotFitInMemoryIsRefusedAtOnce)
{
    LatticeSpec spec;
    spec.countX = 4000;
    spec.countZ = 4000;
    spec.layers = 2;
    EXPECT_EQ(massCountOf(spec), 4000u * 4000u + 3999u * 3999u);
    spec.countX = 12;
    spec.countZ = 12;
    EXPECT_EQ(massCountOf(spec), 265u); // Table 2

    const std::string message = buildError(badScenes + "sheet-too-large-for-memory.json");
    if (availableBytes() > estimatedBytes(loadScene(badScenes + "sheet-too-large-for-memory.json")))
    {
        // Skipped where the sheet fits: the refusal is for machines without the memory, and this one has it.
        GTEST_SKIP() << "this machine has the memory for a 4000x2x4000 sheet; nothing to refuse";
    }
    EXPECT_NE(message.find("sheet.size: a 4000x2x4000 sheet has 31992001 masses and needs about"), std::string::npos)
        << message;
}

// Gravity of 1e200 m/s^2 keeps positions and velocities finite but their speed and kinetic energy overflow;
// the run stops with a NumericalError before a frame or summary could hold them. A scene file cannot give such a
// gravity (SceneFile.ImplausibleValuesAreRefusedNamingTheLikelyMistake); the library's caller can.
TEST(HostileInput, ARunBeyondDoubleRangeStopsBeforeWritingInfinity)
{
    const std::filesystem::path folder = freshFolder("infinite");
    SceneSpec spec =
        parseScene(nlohmann::json::parse(R"({ "sheet": { "size": "4x2x4" }, "environment": { "room": { "enabled":
        false } }, "integrator": { "type": "symplectic" }, "run": { "duration": 0.3, "stop_at_rest": false } })"),
                   source + "/data/scenes", "beyond-range");
    spec.environment.gravity = Vec3(0, -1e200, 0);
    spec.output.framesEvery = 1;
    spec.output.formats = {"vtp"};
    Scene scene(spec);
    RunOptions options;
    options.outDir = (folder / "out").string();
    options.showProgress = false;
    std::ostringstream progress;
    try
    {
        runScene(scene, options, progress);
        FAIL() << "the run went on with an infinite kinetic energy";
    }
    catch (const NumericalError& e)
    {
        // The speed bound stops it first: the bound is finite for any finite gravity.
        EXPECT_EQ(std::string(e.what()).rfind("the simulation diverged at t = 0.03 s: mass 0 moves at ", 0), 0u)
            << e.what();
        EXPECT_NE(std::string(e.what()).find("e+198 m/s, above this scene's bound of 3e+201 m/s"), std::string::npos)
            << e.what();
    }
    EXPECT_FALSE(std::filesystem::exists(folder / "out" / "summary.json"));

    nlohmann::json document = {{"final", {{"kinetic_energy", std::numeric_limits<double>::infinity()}}}};
    try
    {
        requireFiniteJson(document, "summary.json:");
        FAIL() << "an infinite value passed";
    }
    catch (const NumericalError& e)
    {
        EXPECT_NE(std::string(e.what()).find("summary.json: final.kinetic_energy"), std::string::npos) << e.what();
    }
}

// A gravity of 1e100 or 1e308 m/s^2 carries every mass some 1e94 m below the floor in one substep, and the contact pass
// would put them back at rest on no surface (the sheet flat at y = 0, the floor at -2.81 m), ending with exit code 0. A
// scene file refuses such a gravity; given through the library, the guard's speed bound before the contact pass stops
// the run as a diverged one.
TEST(HostileInput, ExtremeGravityStopsAsADivergedRunBeforeTheContactHidesIt)
{
    for (const Real gravity : {1e100, 1e308})
    {
        SceneSpec spec = parseScene(nlohmann::json::parse(R"({ "sheet": { "size": "4x2x4" }, "integrator": {
            "type": "symplectic" }, "run": { "duration": 0.3, "stop_at_rest": false } })"),
                                    source + "/data/scenes", "falling");
        spec.environment.gravity = Vec3(0, -gravity, 0);
        Scene scene(spec);
        const std::string message = test::guardMessageOfRun(scene);
        EXPECT_EQ(message.rfind("the simulation diverged at t = ", 0), 0u) << gravity << ": " << message;
        EXPECT_NE(message.find("before the contact pass"), std::string::npos) << gravity << ": " << message;
    }
}

// Edge contact under extreme motion (the knife-edge scene with a gravity of 1e150 m/s^2) stops the run as a diverged
// one, naming the mass, rather than ending in "double free or corruption" inside Bullet's tree of the sheet's edge
// contact, which boxes that large break.
TEST(HostileInput, EdgeContactUnderExtremeMotionStopsAsADivergedRun)
{
    SceneFlags flags;
    flags.size = "8x2x8";
    flags.duration = "0.3";
    SceneSpec spec = loadScene(source + "/data/scenes/knife-edge.json", flags);
    spec.environment.gravity = Vec3(0, -1e150, 0);
    Scene scene(spec);
    const std::string message = test::guardMessageOfRun(scene);
    EXPECT_EQ(message.rfind("the simulation diverged at t = ", 0), 0u) << message;
    EXPECT_NE(message.find("mass "), std::string::npos) << message;
}

// The last step is shortened so the run ends on its duration: 0.1 s at dt = 0.03 s is 0.1 s, not 0.12 s.
TEST(HostileInput, ARunEndsOnItsDurationExactly)
{
    SceneSpec spec = loadScene(source + "/data/scenes/slope.json");
    spec.time.dt = 0.03;
    spec.run.duration = 0.1;
    spec.run.stopAtRest = false;
    Scene scene(spec);
    while (!scene.finished())
    {
        scene.step();
    }
    EXPECT_EQ(scene.steps(), 4u);
    EXPECT_NEAR(scene.time(), 0.1, 1e-12);
}

// An output folder that holds files is refused without force; with it, the old folder is replaced only when
// the run commits, and a run that fails (never commits) leaves the old folder as it was and no staging folder.
TEST(HostileInput, OutputFoldersNeverMixRuns)
{
    const std::filesystem::path folder = freshFolder("out-folder");
    const std::string target = (folder / "run").string();
    {
        OutputFolder first(target, false);
        writeText(std::filesystem::path(first.staging()) / "summary.json", "first");
        writeText(std::filesystem::path(first.staging()) / "frame_000001.vtp", "first");
        EXPECT_FALSE(std::filesystem::exists(target)) << "written under the final name before the run finished";
        first.commit();
    }
    EXPECT_TRUE(std::filesystem::exists(folder / "run" / "frame_000001.vtp"));
    EXPECT_NE(inputErrorOf([&] { OutputFolder again(target, false); }).find("already holds a run (summary.json)"),
              std::string::npos);
    {
        OutputFolder failed(target, true);
        writeText(std::filesystem::path(failed.staging()) / "summary.json", "failed");
    } // no commit: the run failed
    std::ifstream kept(folder / "run" / "summary.json");
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(kept), {}), "first");
    {
        OutputFolder second(target, true);
        writeText(std::filesystem::path(second.staging()) / "summary.json", "second");
        second.commit();
    }
    EXPECT_FALSE(std::filesystem::exists(folder / "run" / "frame_000001.vtp")) << "a stale frame of the first run";
    std::size_t entries = 0;
    for ([[maybe_unused]] const auto& entry : std::filesystem::directory_iterator(folder))
    {
        ++entries;
    }
    EXPECT_EQ(entries, 1u) << "a staging or old folder was left beside the output";
}

// A study's case folder holds the case's scene.json and run.log before its run, listed by the study in the folder's
// manifest: the run is written in beside them, and they are carried over (the log by a hard link, so what the run
// prints after its commit still lands in it). Without the manifest, they are the user's, and the run is refused.
TEST(HostileInput, OutputFoldersKeepTheFilesAStudyPutThere)
{
    const std::filesystem::path folder = freshFolder("out-beside");
    std::filesystem::create_directories(folder / "case");
    writeText(folder / "case" / "scene.json", "{}");
    EXPECT_NE(inputErrorOf([&] { OutputFolder out((folder / "case").string(), false); })
                  .find("holds files MaSSE did not write (scene.json)"),
              std::string::npos);
    keepInOutputFolder((folder / "case").string(), {"scene.json", "run.log", "status.txt"});
    std::ofstream log(folder / "case" / "run.log");
    log << "before the commit\n" << std::flush;
    {
        OutputFolder out((folder / "case").string(), false);
        writeText(std::filesystem::path(out.staging()) / "summary.json", "run");
        std::filesystem::create_directories(std::filesystem::path(out.staging()) / "frames");
        EXPECT_FALSE(std::filesystem::exists(folder / "case" / "summary.json"));
        out.commit();
    }
    log << "after the commit\n" << std::flush;
    EXPECT_TRUE(std::filesystem::exists(folder / "case" / "scene.json"));
    EXPECT_TRUE(std::filesystem::exists(folder / "case" / "summary.json"));
    EXPECT_TRUE(std::filesystem::is_directory(folder / "case" / "frames"));
    std::ifstream logged(folder / "case" / "run.log");
    EXPECT_EQ(std::string(std::istreambuf_iterator<char>(logged), {}), "before the commit\nafter the commit\n");

    // The study's status.txt comes after the run; a study's clearing removes the run's files and its own, but the
    // scene and a file the user added.
    writeText(folder / "case" / "status.txt", "exit_code=0\n");
    writeText(folder / "case" / "notes.txt", "mine");
    removeListedOutputs((folder / "case").string(), {"scene.json"});
    for (const char* gone : {"summary.json", "frames", "run.log", "status.txt"})
    {
        EXPECT_FALSE(std::filesystem::exists(folder / "case" / gone)) << gone;
    }
    EXPECT_TRUE(std::filesystem::exists(folder / "case" / "scene.json"));
    EXPECT_TRUE(std::filesystem::exists(folder / "case" / "notes.txt"));
}

// Names the file system cannot hold and files where a folder should be are refused before anything runs.
TEST(HostileInput, OutputFoldersThatCannotBeWrittenAreRefusedUpFront)
{
    const std::filesystem::path folder = freshFolder("out-bad");
    const std::string longName = (folder / std::string(300, 'x')).string();
    EXPECT_NE(inputErrorOf([&] { OutputFolder out(longName, false); }).find("has a name of 300 bytes"),
              std::string::npos);
    writeText(folder / "file", "not a folder");
    EXPECT_NE(
        inputErrorOf([&] { OutputFolder out((folder / "file").string(), false); }).find("exists and is not a folder"),
        std::string::npos);
    EXPECT_NE(inputErrorOf([&] { OutputFolder out((folder / "file" / "sub").string(), false); }).find("cannot be"),
              std::string::npos);
}

// What a run killed with -9 leaves (a staging folder with its marker, a temporary file, in MaSSE's own forms) is
// removed by the next run that writes there; a live process's are kept. Names of any other form stay
// (tests/scene/output/OutputFolderTest.cpp).
TEST(HostileInput, LaterRunsRemoveTheLeftoversOfKilledOnes)
{
    const std::filesystem::path folder = freshFolder("leftovers");
    const std::string dead = std::to_string(deadProcess());
    const std::string staging = ".run.masse-partial-" + dead + "-0123abcd";
    std::filesystem::create_directories(folder / staging);
    writeText(folder / staging / ".masse-manifest.json", "{}");
    writeText(folder / staging / "frame_000000.vtp", "half");
    writeText(folder / ("summary.json.masse-tmp-" + dead), "half");
    writeText(folder / ("events.csv.masse-tmp-" + std::to_string(::getpid())), "ours, still running");
    {
        OutputFolder out((folder / "run").string(), false);
        EXPECT_FALSE(std::filesystem::exists(folder / staging));
        EXPECT_FALSE(std::filesystem::exists(folder / ("summary.json.masse-tmp-" + dead)));
        EXPECT_TRUE(std::filesystem::exists(folder / ("events.csv.masse-tmp-" + std::to_string(::getpid()))));
    }

    const std::filesystem::path single = freshFolder("leftover-file");
    writeText(single / ("expected.json.masse-tmp-" + dead), "half");
    writeFileAtomically((single / "expected.json").string(), "{}\n");
    EXPECT_FALSE(std::filesystem::exists(single / ("expected.json.masse-tmp-" + dead)));
}

// Whatever changes a scene's sheet after its file is read (--size, the paper's sizes, the viewer's panel), building the
// scene checks every mass index it names against the sheet that is built: mass 200 of a 16 x 2 x 16 sheet does not
// exist in an 8 x 2 x 8 one (113 masses), and its sag must not be reported as 0.
TEST(HostileInput, MassIndicesAreCheckedAgainstTheSheetThatIsBuilt)
{
    const std::filesystem::path folder = freshFolder("resized");
    writeText(folder / "sag.json", R"({ "sheet": { "size": "16x2x16" }, "report": { "sag": { "mass": 200 } } })");
    SceneSpec spec = loadScene((folder / "sag.json").string());
    spec.sheet.lattice.countX = 8;
    spec.sheet.lattice.countZ = 8;
    const std::string message = inputErrorOf([&] { Scene scene(spec); });
    EXPECT_NE(message.find("sag.json: report.sag.mass: 200 is beyond the sheet's 113 masses"), std::string::npos)
        << message;
}
