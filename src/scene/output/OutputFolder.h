#pragma once
/// An output folder that never mixes runs and never keeps half a run: everything is written into a staging folder
/// beside it (".NAME.partial-PID"), which replaces the folder in one rename when the run succeeds and is removed when
/// it fails. A run killed outright leaves its staging folder behind; the next run into the same folder removes it.
///
/// A folder that already holds a run (summary.json, events.csv, frames/, compare.json or figure18.csv) is refused
/// unless `force` is given; with it, the old folder is replaced whole, only once the new run is complete. A folder
/// holding other files only (a study's case folder with its scene.json and run.log) keeps them: the run's files are
/// renamed into it one by one when the run has finished.

#include <cstddef>
#include <string>

namespace masse::scene
{
class OutputFolder
{
public:
    /// Checks `path` and its parent and creates the staging folder; throws InputError naming `flag` and the path for
    /// a name too long, a file where the folder should be, a folder that holds files (without `force`), a folder
    /// or parent that cannot be written. An empty `path` means no output: every member does nothing.
    OutputFolder(const std::string& path, bool force, const std::string& flag = "--out");
    /// Removes the staging folder, and the parent folders it had to create, unless commit() replaced the target.
    ~OutputFolder();
    OutputFolder(const OutputFolder&) = delete;
    OutputFolder& operator=(const OutputFolder&) = delete;

    /// Where to write while the run goes on ("" without output).
    const std::string& staging() const { return m_staging; }
    /// Moves the staging folder to the target's name, replacing what was there (throws std::runtime_error naming
    /// the folder if a rename fails; the earlier folder is then still in place).
    void commit();

private:
    std::string m_target;
    std::string m_staging;
    std::string m_createdParent; ///< the outermost missing parent this created, "" if none
    bool m_beside = false;       ///< the target holds other files: move the run's files in beside them
    bool m_committed = false;

    void commitBeside(const std::string& old);
};

/// Removes leftovers of killed MaSSE processes in `directory`: files "NAME.tmp-PID" and folders ".NAME.partial-PID"
/// or ".NAME.old-PID" whose process no longer runs. Returns how many it removed; never throws.
std::size_t removeStaleLeftovers(const std::string& directory);
} // namespace masse::scene
