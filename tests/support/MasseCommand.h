#pragma once
/// Runs the `masse` command built with the tests (MASSE_EXECUTABLE) and collects its exit code and output: shared by
/// the command-line, sweep and forming tests.

#include <array>
#include <cstdio>
#include <string>
#include <sys/wait.h>

namespace
{
struct Outcome
{
    int exitCode;
    std::string output; // stdout and stderr together
};

Outcome runMasse(const std::string& arguments)
{
    const std::string command = std::string(MASSE_EXECUTABLE) + " " + arguments + " 2>&1";
    FILE* pipe = ::popen(command.c_str(), "r");
    std::string output;
    std::array<char, 512> buffer{};
    while (pipe && std::fgets(buffer.data(), int(buffer.size()), pipe))
    {
        output += buffer.data();
    }
    const int status = pipe ? ::pclose(pipe) : -1;
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, output};
}
} // namespace
