#pragma once
/// An output folder that never mixes runs, never keeps half a run, and never loses a file MaSSE did not write.
///
/// Everything is written into a staging folder beside the target (".NAME.masse-partial-PID-RANDOM"), which replaces
/// the target when the run succeeds and is removed when it fails. Every output folder holds a manifest
/// (.masse-manifest.json) listing what in it is MaSSE's: the files and folders the run wrote, and the files a study
/// put there for the run (a case's scene.json, run.log and status.txt), which a replacement carries over.
///
/// The target may be missing, empty, or hold only what its manifest lists. A folder that holds anything else (the
/// user's scene, notes.txt) is refused, with `force` or without, naming those files. One that holds an earlier run is
/// refused unless `force` is given; with it, the earlier run is replaced once the new one is complete, by two renames
/// (the target to ".NAME.masse-old-PID-RANDOM", the staging folder to the target). A run killed between them leaves
/// no folder under the target's name; the next run into it renames the old folder back first.
///
/// Runs into one folder take a lock (flock on ".NAME.masse-lock" beside it): a second run is refused while the first
/// writes. Leftovers of killed runs are removed only in MaSSE's own forms: a file "NAME.masse-tmp-PID", a folder of
/// the forms above holding MaSSE's manifest (or empty), PID a process that no longer runs.

#include <cstddef>
#include <string>
#include <vector>

namespace masse::scene
{
/// The name of the manifest in an output folder (and the marker inside a staging folder).
inline constexpr const char* manifestName = ".masse-manifest.json";

/// What in an output folder is MaSSE's, as paths relative to the folder ("frames", "frames/frame_000000.vtp").
struct OutputManifest
{
    std::vector<std::string> written; ///< what the run wrote: replaced by the next forced run
    std::vector<std::string> kept;    ///< what a study put there for the run: carried over by a replacement
};

/// Writes FOLDER/.masse-manifest.json (atomically; throws std::runtime_error if it cannot).
void writeManifest(const std::string& folder, const OutputManifest& manifest);

/// Says that `names` (files directly in `folder`, which may not exist yet) are MaSSE's and kept by the runs into the
/// folder: a study's case folder before its run. Keeps what the folder's manifest listed already.
void keepInOutputFolder(const std::string& folder, const std::vector<std::string>& names);

/// Removes what the manifest of `folder` lists as written, and the kept files other than `keep`; never a file the
/// manifest does not list. A study clears a case folder with it before the case runs again.
void removeListedOutputs(const std::string& folder, const std::vector<std::string>& keep);

class OutputFolder
{
public:
    /// Checks `path` and its parent, takes the folder's lock and creates the staging folder; throws InputError naming
    /// `flag` and the path for a name too long, a file where the folder should be, a folder holding files MaSSE did
    /// not write, an earlier run (without `force`), another run writing there, or a folder or parent that cannot be
    /// written. An empty `path` means no output: every member does nothing.
    OutputFolder(const std::string& path, bool force, const std::string& flag = "--out");
    /// Removes the staging folder, and the parent folders it created if they are empty, unless commit() replaced the
    /// target; releases the lock.
    ~OutputFolder();
    OutputFolder(const OutputFolder&) = delete;
    OutputFolder& operator=(const OutputFolder&) = delete;

    /// Where to write while the run goes on ("" without output).
    const std::string& staging() const { return m_staging; }
    /// Writes the manifest and moves the staging folder to the target's name, replacing what was there (throws
    /// std::runtime_error naming the folder if the target now holds a file MaSSE did not write, or a rename fails;
    /// the earlier folder is then still in place).
    void commit();

private:
    std::string m_flag;
    std::string m_target;
    std::string m_staging;
    std::string m_createdParent; ///< the outermost missing parent this created, "" if none
    std::string m_lockFile;
    int m_lock = -1;
    bool m_committed = false;

    void lock(const std::string& path);
    void unlock();
    void removeCreatedParents() const;
};

/// Removes leftovers of killed MaSSE processes in `directory`: files "NAME.masse-tmp-PID" and folders
/// ".NAME.masse-partial-PID-RANDOM" holding a manifest (or empty), PID a process that no longer runs. Returns how
/// many it removed; never throws.
std::size_t removeStaleLeftovers(const std::string& directory);

/// The name of a temporary file for `path` in MaSSE's own form, which removeStaleLeftovers recognises.
std::string temporaryName(const std::string& path);
} // namespace masse::scene
