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
