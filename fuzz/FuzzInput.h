#pragma once
// What every harness shares: a private folder per process into which the input is written as a file (the readers
// read files: a scene's "extends" and material paths resolve beside it), and the one exception a reader may throw.

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <unistd.h>

namespace masse::fuzz
{
/// A folder of this process's own under the system's temporary folder, made on first use and removed at exit.
inline const std::filesystem::path& workFolder()
{
    struct Folder
    {
        std::filesystem::path path =
            std::filesystem::temp_directory_path() / ("masse-fuzz-" + std::to_string(::getpid()));
        Folder() { std::filesystem::create_directories(path); }
        ~Folder()
        {
            std::error_code ignored;
            std::filesystem::remove_all(path, ignored);
        }
    };
    static const Folder folder;
    return folder.path;
}

/// Writes the fuzzer's bytes to `name` in the work folder and returns its path.
inline std::string writeInput(const std::uint8_t* data, std::size_t size, const std::string& name)
{
    const std::filesystem::path path = workFolder() / name;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(data), std::streamsize(size));
    return path.string();
}

/// Copies a file of the repository's data folder into the work folder once (a base scene, a material).
inline void provide(const std::string& repositoryFile, const std::string& name)
{
    const std::filesystem::path target = workFolder() / name;
    if (!std::filesystem::exists(target))
    {
        std::filesystem::copy_file(std::filesystem::path(MASSE_SOURCE_DIR) / repositoryFile, target);
    }
}
} // namespace masse::fuzz
