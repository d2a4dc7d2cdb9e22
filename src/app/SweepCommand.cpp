/// `masse sweep STUDY --out DIR`: a parameter study, run here with --jobs worker processes or as a Slurm job array
/// with --slurm; `masse sweep --collect DIR` gathers results.csv, plots and a table. The study format:
/// data/studies/README.md.

#include "Commands.h"
#include "SceneOptions.h"

#include "core/Format.h"
#include "core/InputError.h"
#include "scene/output/AtomicFile.h"
#include "scene/study/Study.h"
#include "scene/study/StudyFolder.h"
#include "scene/study/StudyLocal.h"
#include "scene/study/StudyResults.h"
#include "scene/study/StudySlurm.h"

#include <CLI/CLI.hpp>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <sstream>
#include <stdexcept>
#include <unistd.h>

namespace masse::app
{
namespace
{
namespace fs = std::filesystem;

struct SweepOptions
{
    std::string study;
    std::string out;
    std::string collect;
    int jobs = 1;
    int threads = 0;
    bool retryFailed = false;
    bool slurm = false;
    std::string partition;
    std::string timeLimit = "01:00:00";
    int cpusPerTask = 0;
    int throttle = 0;
    bool wait = false;
    bool noPlots = false;
};

/// The first executable `name` on $PATH, or "".
std::string findOnPath(const std::string& name)
{
    const char* path = std::getenv("PATH");
    std::stringstream folders(path ? path : "");
    std::string folder;
    while (std::getline(folders, folder, ':'))
    {
        const fs::path candidate = fs::path(folder.empty() ? "." : folder) / name;
        if (::access(candidate.c_str(), X_OK) == 0)
        {
            return candidate.string();
        }
    }
    return "";
}

/// Writes results.csv and the plots and prints the table; returns the results.
scene::StudyResults collectAndReport(const std::string& dir, bool plots)
{
    const scene::StudyResults results = scene::collectResults(dir);
    scene::writeFileAtomically((fs::path(dir) / "results.csv").string(), scene::resultsCsv(results));
    std::printf("%s", scene::resultsTable(results).c_str());
    std::printf("\n%zu case(s): %zu done, %zu failed, %zu not run; wrote %s/results.csv\n", results.cases.size(),
                results.done, results.failed, results.notRun, dir.c_str());
    if (plots && results.done > 0)
    {
        const std::vector<std::string> written = scene::plotResults(results, dir);
        if (!written.empty())
        {
            std::printf("plots: %s/plots/ (%zu, each output against each varied key)\n", dir.c_str(), written.size());
        }
    }
    return results;
}

/// Names each failed case of a collection on stderr, its folder and why, as the local sweep names a case when it
/// fails; throws (exit 1) if there is one. Cases not run yet are no failure: a study still running on Slurm is
/// collected as far as it has got.
void failOnFailedCases(const scene::StudyResults& results, const std::string& dir)
{
    if (results.failed == 0)
    {
        return;
    }
    std::fflush(stdout);
    for (const scene::CollectedCase& c : results.cases)
    {
        if (c.status == "failed")
        {
            std::fprintf(stderr, "case %04zu failed (exit code %d) in %s: %s\n", c.index, c.exitCode,
                         scene::caseFolder(dir, c.index).c_str(),
                         c.message.empty() ? "its run.log names no error" : c.message.c_str());
        }
    }
    throw std::runtime_error(std::to_string(results.failed) + " case(s) failed; results.csv says why");
}

void checkOptions(const SweepOptions& options)
{
    if (!options.collect.empty())
    {
        if (!options.study.empty() || !options.out.empty() || options.slurm)
        {
            throw InputError("--collect DIR: give it alone (it reads the study from DIR/study.json)");
        }
        return;
    }
    if (options.study.empty() || options.out.empty())
    {
        throw InputError("sweep: give a study and --out DIR (masse sweep STUDY.json --out DIR), or --collect DIR");
    }
    if (options.jobs < 1)
    {
        throw InputError("--jobs: must be >= 1 (got " + std::to_string(options.jobs) + ")");
    }
    if (options.threads < 0 || options.cpusPerTask < 0 || options.throttle < 0)
    {
        throw InputError(std::string(options.threads < 0       ? "--threads"
                                     : options.cpusPerTask < 0 ? "--cpus-per-task"
                                                               : "--throttle") +
                         ": must be >= 0");
    }
    const bool slurmOnly = !options.partition.empty() || options.cpusPerTask > 0 || options.throttle > 0 ||
                           options.wait || options.timeLimit != "01:00:00";
    if (slurmOnly && !options.slurm)
    {
        throw InputError("--partition, --time, --cpus-per-task, --throttle and --wait go with --slurm");
    }
    if (options.slurm && options.jobs != 1)
    {
        throw InputError("--jobs: runs cases here; with --slurm the cluster runs them (use --throttle to limit "
                         "how many at once)");
    }
    for (char c : options.timeLimit)
    {
        if (!std::isdigit(static_cast<unsigned char>(c)) && c != ':' && c != '-')
        {
            throw InputError("--time: expected a Slurm time limit such as 30, 1:00:00 or 2-00:00:00 (got '" +
                             options.timeLimit + "')");
        }
    }
}

/// What sbatch prints when no controller can be found or reached (Slurm 21 to 23).
constexpr const char* noClusterSigns[] = {"Could not establish a configuration source",
                                          "Unable to contact slurm controller",
                                          "DNS SRV lookup failed",
                                          "resolve_ctls_from_dns_srv",
                                          "Connection refused",
                                          "slurm.conf"};

/// The last non-empty line of `text`.
std::string lastLine(const std::string& text)
{
    std::string last;
    std::istringstream lines(text);
    std::string line;
    while (std::getline(lines, line))
    {
        if (!line.empty())
        {
            last = line;
        }
    }
    return last;
}

int submitToSlurm(const scene::Study& study, const std::string& dir, const std::vector<std::size_t>& cases,
                  const SweepOptions& options)
{
    scene::SlurmOptions slurm;
    slurm.masse = scene::currentExecutable();
    slurm.jobName = "masse-" + study.name;
    slurm.partition = options.partition;
    slurm.timeLimit = options.timeLimit;
    slurm.threads = std::max(1, options.threads);
    slurm.cpusPerTask = options.cpusPerTask > 0 ? options.cpusPerTask : slurm.threads;
    slurm.throttle = options.throttle;
    const std::string script = (fs::path(dir) / "sweep.sbatch").string();
    fs::create_directories(fs::path(dir) / "slurm");
    scene::writeFileAtomically(script, scene::sbatchScript(dir, cases, slurm));
    std::printf("wrote %s: a job array of %zu task(s), one per case (--array=%s%s)\n", script.c_str(), cases.size(),
                scene::slurmArrayList(cases).c_str(),
                options.throttle > 0 ? ("%" + std::to_string(options.throttle)).c_str() : "");
    const std::string sbatch = findOnPath("sbatch");
    if (sbatch.empty())
    {
        std::printf("sbatch is not on this machine's PATH: on the cluster's login node run\n  sbatch %s\nand when "
                    "the array has finished\n  masse sweep --collect %s\n",
                    script.c_str(), dir.c_str());
        return 0;
    }
    const std::string command =
        "'" + sbatch + "' --parsable" + (options.wait ? " --wait" : "") + " '" + script + "' 2>&1";
    std::fflush(stdout);
    FILE* pipe = ::popen(command.c_str(), "r");
    if (!pipe)
    {
        throw std::runtime_error("cannot run sbatch");
    }
    std::string output;
    char buffer[256];
    while (std::fgets(buffer, sizeof(buffer), pipe))
    {
        output += buffer;
    }
    const int status = ::pclose(pipe);
    while (!output.empty() && (output.back() == '\n' || output.back() == '\r'))
    {
        output.pop_back();
    }
    const std::string job = output.substr(0, output.find_first_of(";\n"));
    const bool submitted = !job.empty() && job.find_first_not_of("0123456789") == std::string::npos;
    if (!submitted || (status != 0 && !options.wait))
    {
        // sbatch installed on a machine that no Slurm controller serves explains itself in DNS and configuration
        // lookups: say what that means and what to do.
        const bool noCluster = std::any_of(std::begin(noClusterSigns), std::end(noClusterSigns),
                                           [&](const char* sign) { return output.find(sign) != std::string::npos; });
        if (noCluster)
        {
            throw std::runtime_error(
                "no Slurm cluster answers this machine's sbatch (" + lastLine(output) +
                "): configure Slurm here (slurm.conf, or run on the cluster's login node: sbatch " + script +
                "), or run the cases on this machine with --jobs N instead of --slurm");
        }
        throw std::runtime_error("sbatch refused the job array: " + output);
    }
    scene::writeFileAtomically((fs::path(dir) / "slurm" / "job.txt").string(), job + "\n");
    if (options.wait)
    {
        std::printf("job array %s finished%s\n", job.c_str(),
                    status != 0 ? " (some tasks failed; their cases say why)" : "");
        return 1;
    }
    std::printf("submitted job array %s; follow it with: squeue -j %s\nwhen it has finished: masse sweep --collect "
                "%s\n",
                job.c_str(), job.c_str(), dir.c_str());
    return 0;
}

void runSweep(const SweepOptions& options)
{
    checkOptions(options);
    if (!options.collect.empty())
    {
        failOnFailedCases(collectAndReport(options.collect, !options.noPlots), options.collect);
        return;
    }
    // Every case's scene is read and checked before the output folder is touched.
    const scene::Study study = scene::loadStudy(options.study);
    const std::string dir = fs::absolute(options.out).lexically_normal().string();
    scene::prepareStudyFolder(study, dir);
    const std::vector<std::size_t> cases = scene::casesToRun(dir, study.cases.size(), options.retryFailed);
    std::printf("study %s: %zu case(s) (%s) of %s; %zu to run, %zu finished earlier\n", study.name.c_str(),
                study.cases.size(), study.design.c_str(), study.scenePath.c_str(), cases.size(),
                study.cases.size() - cases.size());
    if (options.slurm)
    {
        if (cases.empty())
        {
            failOnFailedCases(collectAndReport(dir, !options.noPlots), dir);
            return;
        }
        if (submitToSlurm(study, dir, cases, options) == 1)
        {
            const scene::StudyResults results = collectAndReport(dir, !options.noPlots);
            failOnFailedCases(results, dir);
            if (results.notRun > 0)
            {
                throw std::runtime_error(std::to_string(results.notRun) +
                                         " case(s) did not run; results.csv says which");
            }
        }
        return;
    }
    scene::LocalRunOptions local;
    local.masse = scene::currentExecutable();
    local.jobs = options.jobs;
    // One thread per case unless asked: --jobs N cases side by side use N cores (masse run alone takes them all).
    local.threads = std::max(1, options.threads);
    local.terminal = ::isatty(STDERR_FILENO) != 0;
    // Each case in a forked copy of this process, through the same command line as `masse run`. Fork needs a
    // single-threaded sweep: it simulates nothing, so no task pool has started a thread.
    local.runInProcess = masseMain;
    std::fflush(stdout);
    const scene::LocalRunReport report = scene::runCasesLocally(dir, cases, local, std::cerr);
    if (!report.overheadSeconds.empty())
    {
        std::vector<double> overhead = report.overheadSeconds;
        std::vector<double> cpu = report.cpuSeconds;
        std::sort(overhead.begin(), overhead.end());
        std::sort(cpu.begin(), cpu.end());
        std::printf("ran %zu case(s) in %.2f s with %d worker(s); overhead per case (its wall time minus the "
                    "simulation's): median %.1f ms, max %.1f ms; CPU time of a case's process: median %.1f ms\n",
                    report.ran, report.wallSeconds, options.jobs, 1000 * overhead[overhead.size() / 2],
                    1000 * overhead.back(), 1000 * cpu[cpu.size() / 2]);
    }
    const scene::StudyResults results = collectAndReport(dir, !options.noPlots);
    if (results.failed > 0)
    {
        throw std::runtime_error(std::to_string(results.failed) + " case(s) failed; results.csv says why");
    }
}
} // namespace

void addSweepCommand(CLI::App& app)
{
    auto options = std::make_shared<SweepOptions>();
    CLI::App* command = app.add_subcommand(
        "sweep", "A parameter study: run a scene over varied keys here (--jobs) or as a Slurm job array (--slurm), "
                 "and collect results.csv and plots (--collect)");
    command->add_option("study", options->study, "Study file (JSON; see data/studies/README.md)");
    command->add_option("--out", options->out, "Study folder (made, or resumed if it holds this study)");
    command->add_option("--collect", options->collect, "Collect a study folder: results.csv, plots and a table");
    command->add_option("--jobs", options->jobs, "Cases run at once here (worker processes; default 1)");
    // Checked here, before the study folder is made: a count that `masse run` refuses would fail every case.
    checkThreadCount(
        *command->add_option("--threads", options->threads, "Threads per case, passed to masse run (default 1)"));
    command->add_flag("--retry-failed", options->retryFailed, "Run failed cases again (finished ones never rerun)");
    command->add_flag("--slurm", options->slurm, "Write an sbatch job array over the cases and submit it");
    command->add_option("--partition", options->partition, "Slurm partition (default: the cluster's)");
    command->add_option("--time", options->timeLimit, "Slurm time limit per case (default 01:00:00)");
    command->add_option("--cpus-per-task", options->cpusPerTask, "Slurm CPUs per case (default: --threads or 1)");
    command->add_option("--throttle", options->throttle, "Slurm: at most this many cases at once (0: no limit)");
    command->add_flag("--wait", options->wait, "Slurm: wait for the array to finish, then collect");
    command->add_flag("--no-plots", options->noPlots, "Collect without drawing plots");
    command->callback([options] { runSweep(*options); });
}
} // namespace masse::app
