#pragma once
/// Runs a study's cases on this machine: N worker processes, each `masse run CASE/scene.json --out CASE` (single
/// threaded unless `threads` says otherwise), its output in CASE/run.log and its exit code and wall time in
/// CASE/status.txt. A case that fails is recorded and the others go on. Workers die with the sweep (a killed sweep
/// leaves no orphans writing into case folders), and the cases they left without a status run again on resume.

#include <functional>
#include <ostream>
#include <string>
#include <vector>

namespace masse::scene
{
struct LocalRunOptions
{
    std::string masse;     ///< the masse executable the workers run
    int jobs = 1;          ///< worker processes at once
    int threads = 1;       ///< passed to each run as --threads
    bool terminal = false; ///< progress redrawn in place (else one line per finished case)
    /// When set, a worker runs its case by calling this with the `masse run` command line (the program name first) in
    /// the forked child, instead of executing `masse` again: the same command line and exit code, without loading
    /// the program and its libraries once more (about 20 ms a case, most of a small case's overhead). The sweep must
    /// have no other threads when it forks (see runCasesLocally).
    std::function<int(int argc, char** argv)> runInProcess;
};

struct LocalRunReport
{
    std::size_t ran = 0;
    std::size_t failed = 0;
    double wallSeconds = 0;
    /// Per finished case: its wall time (spawn to exit and status written) minus the simulation's own stepping time
    /// from its summary.json: process start, reading the scene, building it, writing outputs, the sweep's work.
    std::vector<double> overheadSeconds;
    /// Per finished case: the CPU time (user and system) of its `masse run` process. On a loaded machine a case's wall
    /// time includes waiting for a core; this does not.
    std::vector<double> cpuSeconds;
};

/// Runs `cases` (indices) of the study in `dir`; progress on `progress`. With `runInProcess`, the calling process
/// must be single-threaded (a forked child has only the forking thread; anything another thread held stays held).
LocalRunReport runCasesLocally(const std::string& dir, const std::vector<std::size_t>& cases,
                               const LocalRunOptions& options, std::ostream& progress);

/// The path of the running executable (/proc/self/exe), for workers and Slurm tasks.
std::string currentExecutable();
} // namespace masse::scene
