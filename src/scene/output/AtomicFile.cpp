#include "scene/output/AtomicFile.h"

#include "scene/output/OutputFolder.h"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <mutex>
#include <set>
#include <stdexcept>
#include <unistd.h>

namespace masse::scene
{
namespace
{
/// Once per folder and process: temporaries a killed run left there ("NAME.masse-tmp-PID" of a process gone) are
/// removed, so none outlives the next run that writes beside it.
void cleanFolderOnce(const std::string& path)
{
    static std::mutex mutex;
    static std::set<std::string> cleaned;
    const std::string folder = std::filesystem::path(path).parent_path().string();
    const std::lock_guard<std::mutex> lock(mutex);
    if (cleaned.insert(folder).second)
    {
        removeStaleLeftovers(folder);
    }
}
} // namespace

void writeFileAtomically(const std::string& path, const std::string& content)
{
    cleanFolderOnce(path);
    const std::string temporary = temporaryName(path);
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd < 0)
    {
        throw std::runtime_error("cannot write " + path + ": " + std::strerror(errno));
    }
    std::size_t written = 0;
    while (written < content.size())
    {
        const ssize_t n = ::write(fd, content.data() + written, content.size() - written);
        if (n < 0)
        {
            if (errno == EINTR)
            {
                continue;
            }
            const std::string reason = std::strerror(errno);
            ::close(fd);
            ::unlink(temporary.c_str());
            throw std::runtime_error("cannot write " + path + ": " + reason);
        }
        written += std::size_t(n);
    }
    if (::fsync(fd) != 0 || ::close(fd) != 0 || ::rename(temporary.c_str(), path.c_str()) != 0)
    {
        const std::string reason = std::strerror(errno);
        ::unlink(temporary.c_str());
        throw std::runtime_error("cannot write " + path + ": " + reason);
    }
}
} // namespace masse::scene
