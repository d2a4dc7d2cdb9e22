#include "scene/output/OutputFolder.h"

#include "core/InputError.h"

#include <algorithm>
#include <cerrno>
#include <climits>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <sys/stat.h>
#include <unistd.h>

namespace masse::scene
{
namespace fs = std::filesystem;

namespace
{
/// The longest folder name accepted: the file system's limit less the ".partial-PID" decoration of the staging name.
constexpr std::size_t maxFolderName = NAME_MAX - 32;

bool processRuns(long pid)
{
    if (pid <= 0 || pid > long(INT_MAX))
    {
        return false;
    }
    return pid == long(::getpid()) || ::kill(pid_t(pid), 0) == 0 || errno == EPERM;
}

/// The process id at the end of `name` after `marker` ("x.tmp-123" with ".tmp-" -> 123), or -1.
long pidAfter(const std::string& name, const std::string& marker)
{
    const std::size_t at = name.rfind(marker);
    if (at == std::string::npos || at == 0 || at + marker.size() == name.size())
    {
        return -1;
    }
    long pid = 0;
    for (std::size_t i = at + marker.size(); i < name.size(); ++i)
    {
        if (name[i] < '0' || name[i] > '9' || pid > long(INT_MAX))
        {
            return -1;
        }
        pid = pid * 10 + (name[i] - '0');
    }
    return pid;
}

/// What marks a folder as holding the output of an earlier run ("summary.json"), or "" if nothing does.
std::string earlierRunIn(const fs::path& folder)
{
    for (const char* marker : {"summary.json", "events.csv", "frames", "compare.json", "figure18.csv"})
    {
        std::error_code error;
        if (fs::exists(folder / marker, error))
        {
            return marker;
        }
    }
    return "";
}

std::string failure(const std::string& flag, const std::string& path, const std::string& what)
{
    return flag + ": '" + path + "' " + what;
}
} // namespace

std::size_t removeStaleLeftovers(const std::string& directory)
{
    std::size_t removed = 0;
    std::error_code error;
    fs::directory_iterator it(directory.empty() ? "." : directory, error);
    for (; !error && it != fs::directory_iterator(); it.increment(error))
    {
        const std::string name = it->path().filename().string();
        long pid = pidAfter(name, ".tmp-");
        if (pid < 0 && name.size() > 1 && name[0] == '.')
        {
            pid = std::max(pidAfter(name, ".partial-"), pidAfter(name, ".old-"));
        }
        if (pid < 0 || processRuns(pid))
        {
            continue;
        }
        std::error_code ignored;
        if (fs::remove_all(it->path(), ignored) > 0)
        {
            ++removed;
        }
    }
    return removed;
}

OutputFolder::OutputFolder(const std::string& path, bool force, const std::string& flag)
{
    if (path.empty())
    {
        return;
    }
    const fs::path target = fs::absolute(fs::path(path)).lexically_normal();
    fs::path name = target.filename();
    if (name.empty()) // "dir/" normalises to "dir/" with an empty file name
    {
        name = target.parent_path().filename();
    }
    const fs::path folder = target.filename().empty() ? target.parent_path() : target;
    if (name.empty() || name == "." || name == "..")
    {
        throw InputError(failure(flag, path, "does not name a folder"));
    }
    for (const fs::path& part : folder)
    {
        if (part.string().size() > maxFolderName)
        {
            throw InputError(failure(flag, path,
                                     "has a name of " + std::to_string(part.string().size()) +
                                         " bytes, over the limit of " + std::to_string(maxFolderName)));
        }
    }
    std::error_code error;
    const fs::file_status status = fs::status(folder, error);
    if (fs::exists(status))
    {
        if (!fs::is_directory(status))
        {
            throw InputError(failure(flag, path, "exists and is not a folder"));
        }
        if (::access(folder.c_str(), W_OK) != 0)
        {
            throw InputError(failure(flag, path, "cannot be written (" + std::string(std::strerror(errno)) + ")"));
        }
        const std::string earlier = earlierRunIn(folder);
        if (!earlier.empty() && !force)
        {
            throw InputError(failure(flag, path,
                                     "already holds a run (" + earlier +
                                         "): choose another folder, or give --force to replace it once this run has "
                                         "finished"));
        }
        // Other files (a study's scene.json and run.log) stay: the run's files are moved in beside them.
        m_beside = earlier.empty() && !fs::is_empty(folder, error);
    }
    const fs::path parent = folder.parent_path();
    // The outermost folder this creates: removed again if the run never commits, so bad input leaves nothing.
    for (fs::path missing = parent; !missing.empty() && !fs::exists(missing, error); missing = missing.parent_path())
    {
        m_createdParent = missing.string();
        if (missing == missing.parent_path())
        {
            break;
        }
    }
    fs::create_directories(parent, error);
    auto abandon = [this]
    {
        std::error_code ignored;
        if (!m_createdParent.empty())
        {
            fs::remove_all(m_createdParent, ignored);
        }
    };
    if (error || ::access(parent.c_str(), W_OK) != 0)
    {
        abandon();
        throw InputError(failure(flag, path,
                                 "cannot be created: its parent folder '" + parent.string() + "' cannot be written" +
                                     (error ? " (" + error.message() + ")" : std::string())));
    }
    removeStaleLeftovers(parent.string());
    m_target = folder.string();
    m_staging = (parent / ("." + name.string() + ".partial-" + std::to_string(::getpid()))).string();
    fs::remove_all(m_staging, error); // our own pid: a leftover of a process that had it before us
    if (::mkdir(m_staging.c_str(), 0755) != 0)
    {
        const std::string reason = std::strerror(errno);
        m_staging.clear();
        abandon();
        throw InputError(failure(flag, path, "cannot be created (" + reason + ")"));
    }
}

OutputFolder::~OutputFolder()
{
    if (!m_committed && !m_staging.empty())
    {
        std::error_code ignored;
        fs::remove_all(m_staging, ignored);
        if (!m_createdParent.empty())
        {
            fs::remove_all(m_createdParent, ignored);
        }
    }
}

void OutputFolder::commit()
{
    if (m_staging.empty() || m_committed)
    {
        return;
    }
    const fs::path target(m_target);
    const std::string old =
        (target.parent_path() / ("." + target.filename().string() + ".old-" + std::to_string(::getpid()))).string();
    std::error_code error;
    if (m_beside)
    {
        commitBeside(old);
        return;
    }
    const bool replacing = fs::exists(target, error);
    if (replacing && ::rename(m_target.c_str(), old.c_str()) != 0)
    {
        throw std::runtime_error("cannot replace " + m_target + ": " + std::strerror(errno));
    }
    if (::rename(m_staging.c_str(), m_target.c_str()) != 0)
    {
        const std::string reason = std::strerror(errno);
        if (replacing)
        {
            ::rename(old.c_str(), m_target.c_str());
        }
        throw std::runtime_error("cannot write " + m_target + ": " + reason);
    }
    m_committed = true;
    if (replacing)
    {
        fs::remove_all(old, error);
    }
}

void OutputFolder::commitBeside(const std::string& old)
{
    // Each file is renamed into place (atomic on its own); a folder of the same name (frames/) is moved aside first,
    // as rename cannot replace a folder that holds files.
    std::error_code error;
    for (const fs::directory_entry& entry : fs::directory_iterator(m_staging, error))
    {
        const fs::path destination = fs::path(m_target) / entry.path().filename();
        // Its own error code: a destination that does not exist yet sets one (ENOENT), which is not a failure to
        // read the staging folder.
        std::error_code missing;
        if (fs::is_directory(destination, missing))
        {
            fs::create_directories(old, error);
            if (::rename(destination.c_str(), (fs::path(old) / entry.path().filename()).c_str()) != 0)
            {
                throw std::runtime_error("cannot replace " + destination.string() + ": " + std::strerror(errno));
            }
        }
        if (::rename(entry.path().c_str(), destination.c_str()) != 0)
        {
            throw std::runtime_error("cannot write " + destination.string() + ": " + std::strerror(errno));
        }
    }
    if (error)
    {
        throw std::runtime_error("cannot read " + m_staging + ": " + error.message());
    }
    m_committed = true;
    fs::remove_all(m_staging, error);
    fs::remove_all(old, error);
}
} // namespace masse::scene
