// The core is the engine alone: it may include Eigen, the standard library and the compiler's vector intrinsics,
// nothing else (no Bullet, no GL).

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

TEST(CoreDependency, CoreIncludesOnlyEigenAndTheStandardLibrary)
{
    const std::filesystem::path core = std::filesystem::path(MASSE_SOURCE_DIR) / "src" / "core";
    ASSERT_TRUE(std::filesystem::is_directory(core)) << core;
    const std::regex include(R"(^\s*#\s*include\s*([<"])([^>"]+)[>"])");
    int files = 0;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(core))
    {
        const std::string ext = entry.path().extension().string();
        if (ext != ".h" && ext != ".cpp")
        {
            continue;
        }
        ++files;
        std::ifstream in(entry.path());
        std::string line;
        while (std::getline(in, line))
        {
            std::smatch match;
            if (!std::regex_search(line, match, include))
            {
                continue;
            }
            const std::string header = match[2];
            if (match[1] == "\"")
            {
                // Quoted includes must name a file of the core itself, by its path from src/ (core/<room>/Name.h).
                EXPECT_EQ(header.rfind("core/", 0), 0u) << entry.path() << ": " << line;
                EXPECT_TRUE(std::filesystem::exists(core.parent_path() / header)) << entry.path() << ": " << line;
                continue;
            }
            const bool eigen = header.rfind("Eigen/", 0) == 0;
            const bool standard = header.find('/') == std::string::npos && header.find('.') == std::string::npos;
            // The compiler's own x86 vector intrinsics (a SIMD path's kernels, behind its target attribute) and its
            // CPUID query (which paths the processor runs): part of the compiler, like the standard library, not a
            // dependency.
            const bool intrinsics = header == "immintrin.h" || header == "cpuid.h";
            EXPECT_TRUE(eigen || standard || intrinsics) << entry.path() << " includes " << header;
        }
    }
    EXPECT_GT(files, 10);
}

// Nothing process-wide in the engine: the program that embeds it reads the environment and passes settings in
// (scene/EngineEnvironment.h for the `masse` command and the Python module), and each Simulator owns or is given its
// task pool. A file of the core that reads an environment variable, or keeps a pool in a variable of static storage,
// fails here.
TEST(CoreDependency, CoreReadsNoEnvironmentAndKeepsNoProcessWidePool)
{
    const std::filesystem::path core = std::filesystem::path(MASSE_SOURCE_DIR) / "src" / "core";
    ASSERT_TRUE(std::filesystem::is_directory(core)) << core;
    const std::regex environment(R"(getenv|\benviron\b|setenv|putenv)");
    // A pool in a static or global variable: `static TaskPool pool`, `static std::unique_ptr<TaskPool>`, an extern
    // declaration, or a shared-pool accessor.
    const std::regex processWidePool(R"(\b(static|extern)\b[^;(){}=]*\bTaskPool\b|sharedPool)");
    int files = 0;
    for (const auto& entry : std::filesystem::recursive_directory_iterator(core))
    {
        const std::string ext = entry.path().extension().string();
        if (ext != ".h" && ext != ".cpp")
        {
            continue;
        }
        ++files;
        std::ifstream in(entry.path());
        std::string line;
        for (int number = 1; std::getline(in, line); ++number)
        {
            EXPECT_FALSE(std::regex_search(line, environment))
                << entry.path() << ":" << number << " reads the environment: " << line;
            EXPECT_FALSE(std::regex_search(line, processWidePool))
                << entry.path() << ":" << number << " keeps a process-wide pool: " << line;
        }
    }
    EXPECT_GT(files, 10);
}
