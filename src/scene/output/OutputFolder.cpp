#include "scene/output/OutputFolder.h"

#include "scene/output/AtomicFile.h"

#include "core/InputError.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <climits>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>
#include <set>
#include <stdexcept>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

namespace masse::scene
{
namespace fs = std::filesystem;

namespace
{
/// The longest folder name accepted: the file system's limit less the decoration of the staging folder's name
/// (".NAME.masse-partial-PID-RANDOM").
constexpr std::size_t maxFolderName = NAME_MAX - 48;

/// How many of the files MaSSE did not write a refusal names.
constexpr std::size_t namedForeignFiles = 5;

const std::string temporaryMarker = ".masse-tmp-";
const std::string partialMarker = ".masse-partial-";
const std::string oldMarker = ".masse-old-";
const std::string lockSuffix = ".masse-lock";

bool processRuns(long pid)
{
    if (pid <= 0 || pid > long(INT_MAX))
    {
        return false;
    }
    return pid == long(::getpid()) || ::kill(pid_t(pid), 0) == 0 || errno == EPERM;
}

/// The number `text` spells in decimal digits only (at most INT_MAX), or -1.
long decimal(const std::string& text)
{
    if (text.empty() || text.size() > 10)
    {
        return -1;
    }
    long value = 0;
    for (const char c : text)
    {
        if (c < '0' || c > '9')
        {
            return -1;
        }
        value = value * 10 + (c - '0');
    }
    return value > long(INT_MAX) ? -1 : value;
}

/// The process id of a temporary file "NAME.masse-tmp-PID", or -1 for any other name.
long temporaryPid(const std::string& name)
{
    const std::size_t at = name.rfind(temporaryMarker);
    if (at == std::string::npos || at == 0)
    {
        return -1;
    }
    return decimal(name.substr(at + temporaryMarker.size()));
}

/// A folder named ".NAME<marker>PID-RANDOM" (RANDOM eight hexadecimal digits): its NAME and PID.
struct FolderLeftover
{
    std::string target;
    long pid = -1;
};

std::optional<FolderLeftover> folderLeftover(const std::string& name, const std::string& marker)
{
    constexpr std::size_t randomDigits = 8;
    const std::size_t at = name.rfind(marker);
    if (name.size() < 2 || name[0] != '.' || at == std::string::npos || at < 2 ||
        name.size() < at + marker.size() + 2 + randomDigits || name[name.size() - randomDigits - 1] != '-')
    {
        return std::nullopt;
    }
    for (std::size_t i = name.size() - randomDigits; i < name.size(); ++i)
    {
        if (!std::isxdigit(static_cast<unsigned char>(name[i])) || std::isupper(static_cast<unsigned char>(name[i])))
        {
            return std::nullopt;
        }
    }
    const long pid = decimal(name.substr(at + marker.size(), name.size() - randomDigits - 1 - (at + marker.size())));
    if (pid < 0)
    {
        return std::nullopt;
    }
    return FolderLeftover{name.substr(1, at - 1), pid};
}

/// Eight hexadecimal digits: the part of a staging or old folder's name that makes it one no user would choose, and
/// that no earlier process with the same id can have used.
std::string randomSuffix()
{
    unsigned value = 0;
    try
    {
        value = std::random_device()();
    }
    catch (const std::exception&)
    {
        value = unsigned(std::chrono::steady_clock::now().time_since_epoch().count());
    }
    char text[16];
    std::snprintf(text, sizeof(text), "%08x", value);
    return text;
}

std::string folderName(const std::string& target, const std::string& marker)
{
    return "." + target + marker + std::to_string(::getpid()) + "-" + randomSuffix();
}

bool holdsManifest(const fs::path& folder)
{
    std::error_code error;
    return fs::is_regular_file(folder / manifestName, error);
}

std::optional<OutputManifest> readManifest(const fs::path& folder)
{
    std::ifstream in(folder / manifestName);
    if (!in)
    {
        return std::nullopt;
    }
    const nlohmann::json document = nlohmann::json::parse(in, nullptr, false);
    if (!document.is_object())
    {
        return std::nullopt;
    }
    OutputManifest manifest;
    for (const auto& [key, list] : {std::pair{"written", &manifest.written}, std::pair{"kept", &manifest.kept}})
    {
        if (!document.contains(key))
        {
            continue;
        }
        if (!document[key].is_array())
        {
            return std::nullopt;
        }
        for (const nlohmann::json& entry : document[key])
        {
            if (!entry.is_string())
            {
                return std::nullopt;
            }
            // Only paths inside the folder: a damaged manifest must not make a run remove or carry anything else.
            const fs::path relative = fs::path(entry.get<std::string>()).lexically_normal();
            if (relative.empty() || relative.is_absolute() || *relative.begin() == ".." || relative == ".")
            {
                continue;
            }
            list->push_back(entry.get<std::string>());
        }
    }
    return manifest;
}

/// Every file and folder in `folder`, at any depth, relative to it and in order; not its manifest.
std::vector<std::string> entriesOf(const fs::path& folder)
{
    std::vector<std::string> entries;
    std::error_code error;
    for (fs::recursive_directory_iterator it(folder, error), end; !error && it != end; it.increment(error))
    {
        const std::string relative = it->path().lexically_relative(folder).generic_string();
        if (relative != manifestName)
        {
            entries.push_back(relative);
        }
    }
    std::sort(entries.begin(), entries.end());
    return entries;
}

/// What in `folder` its manifest does not list.
std::vector<std::string> foreignEntries(const fs::path& folder, const OutputManifest& manifest)
{
    std::set<std::string> listed(manifest.written.begin(), manifest.written.end());
    listed.insert(manifest.kept.begin(), manifest.kept.end());
    std::vector<std::string> foreign;
    for (const std::string& entry : entriesOf(folder))
    {
        if (listed.count(entry) == 0)
        {
            foreign.push_back(entry);
        }
    }
    return foreign;
}

/// "notes.txt, s.json and 3 more".
std::string someOf(const std::vector<std::string>& names)
{
    std::string text;
    for (std::size_t i = 0; i < names.size() && i < namedForeignFiles; ++i)
    {
        text += (i == 0 ? "" : ", ") + names[i];
    }
    if (names.size() > namedForeignFiles)
    {
        text += " and " + std::to_string(names.size() - namedForeignFiles) + " more";
    }
    return text;
}

/// What marks the folder as holding an earlier run ("summary.json"): the first of the run's files its manifest
/// lists that is there, the usual ones first; "" if none is.
std::string earlierRunIn(const fs::path& folder, const OutputManifest& manifest)
{
    std::vector<std::string> candidates = {"summary.json", "events.csv", "frames", "compare.json", "figure18.csv"};
    candidates.insert(candidates.end(), manifest.written.begin(), manifest.written.end());
    for (const std::string& name : candidates)
    {
        std::error_code error;
        if (std::find(manifest.written.begin(), manifest.written.end(), name) != manifest.written.end() &&
            fs::exists(fs::symlink_status(folder / name, error)))
        {
            return name;
        }
    }
    return "";
}

std::string failure(const std::string& flag, const std::string& path, const std::string& what)
{
    return flag + ": '" + path + "' " + what;
}

/// Under the folder's lock: a forced replacement killed between its two renames left the earlier result in
/// ".NAME.masse-old-PID-RANDOM" and no folder named NAME; it is renamed back. Old folders the target has superseded
/// (it exists and is MaSSE's) are removed; any other is left alone.
void restoreInterrupted(const fs::path& parent, const std::string& name)
{
    std::vector<fs::path> old;
    std::error_code error;
    for (fs::directory_iterator it(parent, error); !error && it != fs::directory_iterator(); it.increment(error))
    {
        const std::optional<FolderLeftover> leftover = folderLeftover(it->path().filename().string(), oldMarker);
        std::error_code ignored;
        if (leftover && leftover->target == name && !processRuns(leftover->pid) &&
            fs::is_directory(fs::symlink_status(it->path(), ignored)) && holdsManifest(it->path()))
        {
            old.push_back(it->path());
        }
    }
    std::sort(old.begin(), old.end());
    const fs::path target = parent / name;
    std::error_code missing;
    if (!old.empty() && !fs::exists(fs::symlink_status(target, missing)) &&
        ::rename(old.front().c_str(), target.c_str()) == 0)
    {
        old.erase(old.begin());
    }
    if (fs::is_directory(fs::symlink_status(target, missing)) && holdsManifest(target))
    {
        for (const fs::path& superseded : old)
        {
            std::error_code ignored;
            fs::remove_all(superseded, ignored);
        }
    }
}

/// Gives `file` (in `from`) the same name in `to`: a hard link, so that a log still being written goes on into the
/// file under its new name; a copy where the file system has no hard links.
void carryOver(const fs::path& from, const fs::path& to, const std::string& file)
{
    std::error_code error;
    if (fs::exists(fs::symlink_status(to / file, error)) || !fs::exists(fs::symlink_status(from / file, error)))
    {
        return;
    }
    if (::link((from / file).c_str(), (to / file).c_str()) == 0)
    {
        return;
    }
    fs::copy(from / file, to / file, fs::copy_options::recursive | fs::copy_options::copy_symlinks, error);
    if (error)
    {
        throw std::runtime_error("cannot keep " + (from / file).string() + " in the new output: " + error.message());
    }
}
} // namespace

std::string temporaryName(const std::string& path)
{
    return path + temporaryMarker + std::to_string(::getpid());
}

void writeManifest(const std::string& folder, const OutputManifest& manifest)
{
    const nlohmann::json document = {
        {"masse_output_folder", 1}, {"written", manifest.written}, {"kept", manifest.kept}};
    writeFileAtomically((fs::path(folder) / manifestName).string(), document.dump(1) + "\n");
}

void keepInOutputFolder(const std::string& folder, const std::vector<std::string>& names)
{
    OutputManifest manifest = readManifest(folder).value_or(OutputManifest{});
    bool changed = !holdsManifest(folder);
    for (const std::string& name : names)
    {
        if (std::find(manifest.kept.begin(), manifest.kept.end(), name) == manifest.kept.end())
        {
            manifest.kept.push_back(name);
            changed = true;
        }
    }
    if (changed)
    {
        writeManifest(folder, manifest);
    }
}

void removeListedOutputs(const std::string& folder, const std::vector<std::string>& keep)
{
    const std::optional<OutputManifest> manifest = readManifest(folder);
    if (!manifest)
    {
        return;
    }
    std::vector<std::string> listed = manifest->written;
    for (const std::string& name : manifest->kept)
    {
        if (std::find(keep.begin(), keep.end(), name) == keep.end())
        {
            listed.push_back(name);
        }
    }
    // Deepest first ("frames/frame_000000.vtp" sorts after "frames"); a folder goes only once it is empty, so a file
    // the manifest does not list keeps its folder.
    std::sort(listed.rbegin(), listed.rend());
    for (const std::string& entry : listed)
    {
        std::error_code ignored;
        fs::remove(fs::path(folder) / entry, ignored);
    }
}

std::size_t removeStaleLeftovers(const std::string& directory)
{
    std::size_t removed = 0;
    std::error_code error;
    fs::directory_iterator it(directory.empty() ? "." : directory, error);
    for (; !error && it != fs::directory_iterator(); it.increment(error))
    {
        const std::string name = it->path().filename().string();
        std::error_code ignored;
        const fs::file_status status = fs::symlink_status(it->path(), ignored);
        const long temporary = temporaryPid(name);
        if (temporary >= 0)
        {
            if (fs::is_regular_file(status) && !processRuns(temporary) && fs::remove(it->path(), ignored))
            {
                ++removed;
            }
            continue;
        }
        const std::optional<FolderLeftover> staging = folderLeftover(name, partialMarker);
        if (!staging || processRuns(staging->pid) || !fs::is_directory(status))
        {
            continue;
        }
        // MaSSE's marker inside, or nothing at all (a run killed between making the folder and its marker).
        if (holdsManifest(it->path()) ? fs::remove_all(it->path(), ignored) > 0 : fs::remove(it->path(), ignored))
        {
            ++removed;
        }
    }
    return removed;
}

OutputFolder::OutputFolder(const std::string& path, bool force, const std::string& flag) : m_flag(flag)
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
    }
    const fs::path parent = folder.parent_path();
    // The outermost folder this creates: removed again (if empty) when the run never commits, so bad input leaves
    // nothing.
    for (fs::path missing = parent; !missing.empty() && !fs::exists(missing, error); missing = missing.parent_path())
    {
        m_createdParent = missing.string();
        if (missing == missing.parent_path())
        {
            break;
        }
    }
    m_target = folder.string();
    fs::create_directories(parent, error);
    if (error || ::access(parent.c_str(), W_OK) != 0)
    {
        removeCreatedParents();
        throw InputError(failure(flag, path,
                                 "cannot be created: its parent folder '" + parent.string() + "' cannot be written" +
                                     (error ? " (" + error.message() + ")" : std::string())));
    }
    try
    {
        lock(path);
        restoreInterrupted(parent, name.string());
        removeStaleLeftovers(parent.string());
        if (fs::is_directory(folder, error))
        {
            removeStaleLeftovers(folder.string()); // a killed study's status.txt.masse-tmp-PID
            const OutputManifest manifest = readManifest(folder).value_or(OutputManifest{});
            const std::vector<std::string> foreign = foreignEntries(folder, manifest);
            if (!foreign.empty())
            {
                throw InputError(failure(
                    flag, path,
                    "holds files MaSSE did not write (" + someOf(foreign) + "): " +
                        (force ? "--force replaces only a folder of MaSSE's own output; move them out or choose "
                                 "another folder"
                               : "choose a new or empty folder, or move them out")));
            }
            const std::string earlier = earlierRunIn(folder, manifest);
            if (!earlier.empty() && !force)
            {
                throw InputError(failure(flag, path,
                                         "already holds a run (" + earlier +
                                             "): choose another folder, or give --force to replace it once this run "
                                             "has finished"));
            }
        }
        for (int attempt = 0; m_staging.empty(); ++attempt)
        {
            const std::string staging = (parent / folderName(name.string(), partialMarker)).string();
            if (::mkdir(staging.c_str(), 0755) == 0)
            {
                m_staging = staging;
            }
            else if (errno != EEXIST || attempt > 8)
            {
                throw InputError(failure(flag, path, "cannot be created (" + std::string(std::strerror(errno)) + ")"));
            }
        }
        writeManifest(m_staging, {}); // the marker that lets a later run remove it if this one is killed
    }
    catch (...)
    {
        if (!m_staging.empty())
        {
            fs::remove_all(m_staging, error);
            m_staging.clear();
        }
        unlock();
        removeCreatedParents();
        throw;
    }
}

OutputFolder::~OutputFolder()
{
    if (!m_committed && !m_staging.empty())
    {
        std::error_code ignored;
        fs::remove_all(m_staging, ignored);
    }
    unlock();
    if (!m_committed)
    {
        removeCreatedParents();
    }
}

void OutputFolder::lock(const std::string& path)
{
    const fs::path target(m_target);
    std::string name = target.filename().string();
    name.insert(0, 1, '.'); // not "." + name: GCC 12 warns of a false overlap there (-Wrestrict)
    m_lockFile = (target.parent_path() / (name + lockSuffix)).string();
    for (int attempt = 0; attempt < 16; ++attempt)
    {
        const int fd = ::open(m_lockFile.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
        if (fd < 0)
        {
            throw InputError(failure(
                m_flag, path, "cannot be locked: " + m_lockFile + " cannot be created (" + std::strerror(errno) + ")"));
        }
        if (::flock(fd, LOCK_EX | LOCK_NB) != 0)
        {
            const int reason = errno;
            ::close(fd);
            if (reason == EWOULDBLOCK)
            {
                throw InputError(failure(m_flag, path,
                                         "is in use: another masse run is writing there (it holds " + m_lockFile +
                                             "); wait for it to finish, or choose another folder"));
            }
            // A file system without locks (ENOLCK, EOPNOTSUPP): the run goes on unguarded rather than not at all.
            m_lockFile.clear();
            return;
        }
        // The run that held the lock removes the file when it ends: one opened just before is no longer the lock
        // file, and the lock on it guards nothing. Then the file is made anew.
        struct stat held
        {
        };
        struct stat named
        {
        };
        if (::fstat(fd, &held) == 0 && ::stat(m_lockFile.c_str(), &named) == 0 && held.st_dev == named.st_dev &&
            held.st_ino == named.st_ino)
        {
            m_lock = fd;
            return;
        }
        ::close(fd);
    }
    throw InputError(failure(m_flag, path, "cannot be locked: " + m_lockFile + " keeps being removed"));
}

void OutputFolder::unlock()
{
    if (m_lock >= 0)
    {
        // Removed while still held: a run waiting on this file finds it gone and makes a new one (see lock()).
        ::unlink(m_lockFile.c_str());
        ::close(m_lock);
        m_lock = -1;
    }
}

void OutputFolder::removeCreatedParents() const
{
    if (m_createdParent.empty())
    {
        return;
    }
    // Only empty folders, deepest first: another run may have made the same parents and be writing in them.
    const fs::path outermost(m_createdParent);
    for (fs::path folder = fs::path(m_target).parent_path(); !folder.empty(); folder = folder.parent_path())
    {
        std::error_code error;
        if (!fs::remove(folder, error) || folder == outermost || folder == folder.parent_path())
        {
            break;
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
    const fs::path staging(m_staging);
    std::error_code error;
    const bool replacing = fs::is_directory(target, error) && !fs::is_empty(target, error);
    OutputManifest now;
    if (replacing)
    {
        // Checked again: the user may have put a file there while the run went on.
        now = readManifest(target).value_or(OutputManifest{});
        const std::vector<std::string> foreign = foreignEntries(target, now);
        if (!foreign.empty())
        {
            throw std::runtime_error("cannot replace " + m_target + ": it now holds files MaSSE did not write (" +
                                     someOf(foreign) + "); the new result was not written");
        }
    }
    OutputManifest manifest;
    manifest.kept = now.kept;
    for (const std::string& file : now.kept)
    {
        carryOver(target, staging, file);
    }
    for (const std::string& entry : entriesOf(staging))
    {
        if (std::find(manifest.kept.begin(), manifest.kept.end(), entry) == manifest.kept.end())
        {
            manifest.written.push_back(entry);
        }
    }
    writeManifest(m_staging, manifest);

    if (!replacing)
    {
        // A missing or empty target: one rename (an empty folder is replaced by it).
        if (::rename(m_staging.c_str(), m_target.c_str()) != 0)
        {
            throw std::runtime_error("cannot write " + m_target + ": " + std::strerror(errno));
        }
        m_committed = true;
        return;
    }
    // Two renames. Killed between them, the earlier result waits in the old folder (with its manifest), and the next
    // run into the target renames it back (restoreInterrupted).
    const std::string old = (target.parent_path() / folderName(target.filename().string(), oldMarker)).string();
    if (::rename(m_target.c_str(), old.c_str()) != 0)
    {
        throw std::runtime_error("cannot replace " + m_target + ": " + std::strerror(errno));
    }
    if (::rename(m_staging.c_str(), m_target.c_str()) != 0)
    {
        const std::string reason = std::strerror(errno);
        ::rename(old.c_str(), m_target.c_str());
        throw std::runtime_error("cannot write " + m_target + ": " + reason);
    }
    m_committed = true;
    fs::remove_all(old, error);
}
} // namespace masse::scene
