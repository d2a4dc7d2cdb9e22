#pragma once
/// Writes whole files so that a crash cannot leave a half-written one: the content goes to a temporary file in the
/// same folder, is flushed to disk, and is renamed over the target (rename is atomic on POSIX file systems). The first
/// write into a folder removes the temporaries that killed processes left there.

#include <string>

namespace masse::scene
{
/// Throws std::runtime_error naming the file if it cannot be written.
void writeFileAtomically(const std::string& path, const std::string& content);
} // namespace masse::scene
