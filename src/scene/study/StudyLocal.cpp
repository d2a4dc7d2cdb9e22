#include "scene/study/StudyLocal.h"

#include "scene/study/StudyFolder.h"

#include <nlohmann/json.hpp>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <stdexcept>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

namespace masse::scene
{
namespace
{
using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start)
{
    return std::chrono::duration<double>(Clock::now() - start).count();
}

struct Worker
{
    std::size_t caseIndex = 0;
    Clock::time_point started;
};

/// Starts `masse run` on a case; its stdout and stderr go to run.log. The child asks the kernel to kill it when the
/// sweep dies (PR_SET_PDEATHSIG), so an interrupted sweep leaves no run writing into a case folder.
pid_t startCase(const std::string& caseDir, const LocalRunOptions& options)
{
    const std::string scene = caseDir + "/scene.json";
    const std::string log = caseDir + "/run.log";
    std::vector<std::string> arguments = {options.masse, "run", scene, "--out", caseDir, "--quiet"};
    if (options.threads > 0)
    {
        arguments.push_back("--threads");
        arguments.push_back(std::to_string(options.threads));
    }
    std::vector<char*> argv;
    for (std::string& a : arguments)
    {
        argv.push_back(a.data());
    }
    argv.push_back(nullptr);
    const pid_t parent = ::getpid();
    // What the sweep has buffered must not be written again by the child.
    std::cout.flush();
    std::cerr.flush();
    std::fflush(nullptr);
    const pid_t pid = ::fork();
    if (pid < 0)
    {
        throw std::runtime_error(std::string("cannot start a worker: ") + std::strerror(errno));
    }
    if (pid == 0)
    {
        // Only async-signal-safe calls from here to exec (or to the in-process run, which needs a single-threaded
        // sweep).
        ::prctl(PR_SET_PDEATHSIG, SIGKILL);
        if (::getppid() != parent)
        {
            ::_exit(127); // the sweep died before the prctl took effect
        }
        const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (fd >= 0)
        {
            ::dup2(fd, STDOUT_FILENO);
            ::dup2(fd, STDERR_FILENO);
            ::close(fd);
        }
        if (options.runInProcess)
        {
            const int code = options.runInProcess(int(arguments.size()), argv.data());
            std::cout.flush();
            std::cerr.flush();
            std::fflush(nullptr);
            ::_exit(code);
        }
        ::execv(argv[0], argv.data());
        const char message[] = "masse: cannot start the masse executable for this case\n";
        [[maybe_unused]] const ssize_t ignored = ::write(STDERR_FILENO, message, sizeof(message) - 1);
        ::_exit(127);
    }
    return pid;
}

double simulationSeconds(const std::string& caseDir)
{
    std::ifstream in(caseDir + "/summary.json");
    if (!in)
    {
        return 0;
    }
    const nlohmann::json summary = nlohmann::json::parse(in, nullptr, false);
    if (summary.is_discarded() || !summary.contains("wall_seconds") || !summary["wall_seconds"].is_number())
    {
        return 0;
    }
    return summary["wall_seconds"].get<double>();
}

std::string clock(double seconds)
{
    const long s = std::lround(seconds);
    char text[32];
    std::snprintf(text, sizeof(text), "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
    return text;
}
} // namespace

std::string currentExecutable()
{
    std::error_code error;
    const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
    if (error)
    {
        throw std::runtime_error("cannot find the masse executable (/proc/self/exe): " + error.message());
    }
    return self.string();
}

LocalRunReport runCasesLocally(const std::string& dir, const std::vector<std::size_t>& cases,
                               const LocalRunOptions& options, std::ostream& progress)
{
    LocalRunReport report;
    const Clock::time_point start = Clock::now();
    std::map<pid_t, Worker> running;
    std::size_t next = 0;
    double caseSeconds = 0;
    auto show = [&](const std::string& finishedLine)
    {
        const std::size_t done = report.ran;
        const double elapsed = secondsSince(start);
        // What is left, at the pace so far (wall time per finished case divided over the workers).
        const double left = done > 0 ? caseSeconds / double(done) * double(cases.size() - done) /
                                           double(std::max<std::size_t>(1, std::size_t(options.jobs)))
                                     : 0;
        char line[256];
        std::snprintf(line, sizeof(line), "sweep: %zu/%zu done, %zu failed, %zu running, %s elapsed%s%s", done,
                      cases.size(), report.failed, running.size(), clock(elapsed).c_str(),
                      done > 0 && done < cases.size() ? ", about " : "",
                      done > 0 && done < cases.size() ? (clock(left) + " left").c_str() : "");
        if (options.terminal)
        {
            progress << "\r\033[K" << line << std::flush;
        }
        else
        {
            progress << finishedLine << " (" << line << ")\n" << std::flush;
        }
    };
    while (next < cases.size() || !running.empty())
    {
        while (next < cases.size() && running.size() < std::size_t(std::max(1, options.jobs)))
        {
            const std::size_t index = cases[next++];
            const std::string caseDir = caseFolder(dir, index);
            clearCaseOutputs(caseDir);
            Worker worker{index, Clock::now()};
            running.emplace(startCase(caseDir, options), worker);
        }
        if (options.terminal)
        {
            show("");
        }
        int status = 0;
        struct rusage usage
        {
        };
        const pid_t pid = ::wait4(-1, &status, 0, &usage);
        if (pid < 0)
        {
            if (errno == EINTR)
            {
                continue;
            }
            throw std::runtime_error(std::string("waiting for the workers: ") + std::strerror(errno));
        }
        const auto it = running.find(pid);
        if (it == running.end())
        {
            continue; // not one of ours
        }
        const Worker worker = it->second;
        running.erase(it);
        const int exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
        const std::string caseDir = caseFolder(dir, worker.caseIndex);
        const double wall = secondsSince(worker.started);
        writeCaseStatus(caseDir, exitCode, wall);
        ++report.ran;
        caseSeconds += wall;
        char line[512];
        if (exitCode == 0)
        {
            report.overheadSeconds.push_back(wall - simulationSeconds(caseDir));
            report.cpuSeconds.push_back(double(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
                                        1e-6 * double(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec));
            std::snprintf(line, sizeof(line), "case %04zu done in %.2f s", worker.caseIndex, wall);
        }
        else
        {
            ++report.failed;
            std::snprintf(line, sizeof(line), "case %04zu failed (exit code %d): %s", worker.caseIndex, exitCode,
                          lastLogLine(caseDir).c_str());
            if (options.terminal)
            {
                progress << "\r\033[K" << line << "\n";
            }
        }
        show(line);
    }
    if (options.terminal && !cases.empty())
    {
        progress << "\n";
    }
    report.wallSeconds = secondsSince(start);
    return report;
}
} // namespace masse::scene
