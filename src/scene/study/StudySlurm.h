#pragma once
/// A study on a Slurm cluster: one job array over the cases still to run, each array task running `masse run` on
/// its case and writing the case's run.log and status.txt as a local worker does, so `masse sweep --collect` reads
/// both the same way.

#include <string>
#include <vector>

namespace masse::scene
{
struct SlurmOptions
{
    std::string masse; ///< the masse executable the tasks run (must be reachable from the compute nodes)
    std::string jobName;
    std::string partition; ///< "" leaves it to the cluster's default
    std::string timeLimit = "01:00:00";
    int cpusPerTask = 1;
    int throttle = 0; ///< at most this many tasks at once (0: no limit)
    int threads = 1;  ///< passed to each run as --threads
};

/// "0-3,5,7-9": Slurm's --array list for the indices (sorted, without repeats).
std::string slurmArrayList(const std::vector<std::size_t>& indices);

/// The sbatch script for the given cases of the study in `dir` (an absolute path).
std::string sbatchScript(const std::string& dir, const std::vector<std::size_t>& cases, const SlurmOptions& options);
} // namespace masse::scene
