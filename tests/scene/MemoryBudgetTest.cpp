// The memory estimate against the memory runs really take: a sheet refused for memory must really not fit, and one
// that would not fit must be refused, so the estimate has to cover the peak resident memory of `masse run` without
// asking several times what it needs.

#include "support/Sanitizers.h"

#include "scene/MemoryBudget.h"
#include "scene/SceneFile.h"

#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>
#include <vector>

using namespace masse;
using namespace masse::scene;

namespace
{
const std::string source = MASSE_SOURCE_DIR;

/// Peak resident memory (bytes) of `masse` run with these arguments, from the kernel's account of that child alone
/// (wait4), or -1 if it did not run to a clean exit.
double peakBytesOfRun(const std::vector<std::string>& arguments)
{
    std::vector<char*> argv;
    std::string executable = MASSE_EXECUTABLE;
    argv.push_back(executable.data());
    std::vector<std::string> copies = arguments;
    for (std::string& argument : copies)
    {
        argv.push_back(argument.data());
    }
    argv.push_back(nullptr);
    std::fflush(stdout); // or the child's reopened stdout would write the parent's buffered lines a second time
    const pid_t child = ::fork();
    if (child == 0)
    {
        std::freopen("/dev/null", "w", stdout);
        std::freopen("/dev/null", "w", stderr);
        ::execv(argv[0], argv.data());
        ::_exit(127);
    }
    int status = 0;
    rusage usage{};
    if (child < 0 || ::wait4(child, &status, 0, &usage) != child || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
    {
        return -1;
    }
    return double(usage.ru_maxrss) * 1024; // ru_maxrss is in kilobytes on Linux
}

struct Case
{
    std::string scene;
    std::string size;
    std::string integrator;
    std::string preconditioner;
};
} // namespace

// Each case runs a few steps (the peak comes with the first implicit factorisation and with the reports at the end),
// then checks that the estimate covers the peak and is not more than four times it. The cases span what the estimate
// must follow: the explicit and implicit integrators, the three preconditioners (a sparse factor's fill grows faster
// than the sheet), a thick 3D lattice (whose factor fills far more than a two-layer sheet's) and a forming scene with
// a mould and heat.
TEST(MemoryBudget, TheEstimateCoversWhatARunTakes)
{
    if (test::underAddressSanitizer || test::underThreadSanitizer)
    {
        // Skipped under the sanitizers: their shadow memory and quarantines multiply what a run holds, so the peak
        // measured is not the one the estimate is for (the Release stage runs this test).
        GTEST_SKIP() << "a sanitizer's shadow memory is not the run's own";
    }
    const std::vector<Case> cases = {
        {"sag.json", "96x2x96", "symplectic", "cholesky"},
        {"sag.json", "96x2x96", "implicit", "jacobi"},
        {"sag.json", "96x2x96", "implicit", "multigrid"},
        {"sag.json", "96x2x96", "implicit", "cholesky"},
        {"sag.json", "20x20x20", "implicit", "cholesky"},
        {"sag.json", "96x2x96", "trbdf2", "cholesky"},
        {"vacuum-forming-cup.json", "96x2x96", "implicit", "cholesky"},
    };
    const std::filesystem::path out = std::filesystem::temp_directory_path() / "masse-memory-budget";
    for (const Case& c : cases)
    {
        SCOPED_TRACE(c.scene + " " + c.size + " " + c.integrator + " " + c.preconditioner);
        std::filesystem::remove_all(out);
        const double peak =
            peakBytesOfRun({"run", source + "/data/scenes/" + c.scene, "--size", c.size, "--integrator", c.integrator,
                            "--set", "integrator.preconditioner=" + c.preconditioner, "--set", "integrator.dt=0.002",
                            "--duration", "0.006", "--threads", "1", "--quiet", "--out", out.string()});
        std::filesystem::remove_all(out);
        ASSERT_GT(peak, 0) << "the run failed";
        SceneSpec spec = loadScene(source + "/data/scenes/" + c.scene);
        parseSize(c.size, spec.sheet.lattice);
        spec.time.integrator = parseIntegrator(c.integrator);
        spec.time.implicit.preconditioner = parsePreconditioner(c.preconditioner);
        const double estimate = estimatedBytes(spec);
        std::printf("%-24s %-9s %-10s %-9s peak %7.1f MB, estimate %7.1f MB (%.2fx)\n", c.scene.c_str(), c.size.c_str(),
                    c.integrator.c_str(), c.preconditioner.c_str(), peak / 1e6, estimate / 1e6, estimate / peak);
        EXPECT_GE(estimate, peak);
        EXPECT_LE(estimate, 4 * peak);
    }
}
