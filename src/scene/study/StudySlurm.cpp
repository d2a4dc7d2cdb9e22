#include "scene/study/StudySlurm.h"

#include <sstream>

namespace masse::scene
{
namespace
{
/// A word for sh, in single quotes.
std::string shellQuote(const std::string& text)
{
    std::string quoted = "'";
    for (char c : text)
    {
        quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
    }
    return quoted + "'";
}
} // namespace

std::string slurmArrayList(const std::vector<std::size_t>& indices)
{
    std::ostringstream out;
    for (std::size_t i = 0; i < indices.size();)
    {
        std::size_t j = i;
        while (j + 1 < indices.size() && indices[j + 1] == indices[j] + 1)
        {
            ++j;
        }
        out << (i ? "," : "") << indices[i];
        if (j > i)
        {
            out << "-" << indices[j];
        }
        i = j + 1;
    }
    return out.str();
}

std::string sbatchScript(const std::string& dir, const std::vector<std::size_t>& cases, const SlurmOptions& options)
{
    std::ostringstream s;
    s << "#!/bin/sh\n"
      << "# masse sweep: one Slurm array task per case of " << dir << "\n"
      << "# Written by masse sweep --slurm; submit it again (or rerun masse sweep --slurm) to run the cases that\n"
      << "# have no status.txt yet. Then: masse sweep --collect " << dir << "\n"
      << "#SBATCH --job-name=" << options.jobName << "\n"
      << "#SBATCH --array=" << slurmArrayList(cases);
    if (options.throttle > 0)
    {
        s << "%" << options.throttle;
    }
    s << "\n"
      << "#SBATCH --ntasks=1\n"
      << "#SBATCH --cpus-per-task=" << options.cpusPerTask << "\n"
      << "#SBATCH --time=" << options.timeLimit << "\n";
    if (!options.partition.empty())
    {
        s << "#SBATCH --partition=" << options.partition << "\n";
    }
    s << "#SBATCH --output=" << dir << "/slurm/task-%A_%a.out\n"
      << "set -u\n"
      << "case_dir=$(printf '%s/cases/%04d' " << shellQuote(dir) << " \"$SLURM_ARRAY_TASK_ID\")\n"
      << "cd \"$case_dir\" || exit 2\n"
      << "# What an earlier, interrupted run of this case left goes first (everything but the scene and the manifest\n"
      << "# that says which files are MaSSE's).\n"
      << "find . -mindepth 1 -maxdepth 1 ! -name scene.json ! -name .masse-manifest.json -exec rm -rf {} +\n"
      << "start=$(date +%s.%N)\n"
      << shellQuote(options.masse) << " run scene.json --out . --quiet";
    if (options.threads > 0)
    {
        s << " --threads " << options.threads;
    }
    s << " >run.log 2>&1\n"
      << "code=$?\n"
      << "# The run put a new folder in the case folder's place (scene.json and run.log carried over): into it.\n"
      << "cd \"$case_dir\" || exit 2\n"
      << "end=$(date +%s.%N)\n"
      << "# status.txt last, whole or not at all: it is what says the case is finished.\n"
      << "printf 'exit_code=%d\\nwall_seconds=%s\\n' \"$code\" \"$(awk \"BEGIN { print $end - $start }\")\" "
         ">status.txt.tmp\n"
      << "mv status.txt.tmp status.txt\n"
      << "exit \"$code\"\n";
    return s.str();
}
} // namespace masse::scene
