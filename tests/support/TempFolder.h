#pragma once
// An empty folder of the test's own under GoogleTest's temporary directory.

#include <gtest/gtest.h>

#include <filesystem>
#include <string>

namespace masse::test
{
/// TempDir()/name, emptied of what an earlier run left and created.
inline std::filesystem::path freshTempFolder(const std::string& name)
{
    const std::filesystem::path folder = std::filesystem::path(testing::TempDir()) / name;
    std::filesystem::remove_all(folder);
    std::filesystem::create_directories(folder);
    return folder;
}
} // namespace masse::test
