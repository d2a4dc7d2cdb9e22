#include "scene/output/Plot.h"

#include "scene/output/AtomicFile.h"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <unistd.h>

namespace masse::scene
{
void plotPng(const std::string& script, const std::string& pngPath, int width, int height)
{
    const std::string stem = pngPath + ".tmp-" + std::to_string(::getpid());
    const std::string scriptPath = stem + ".gp";
    const std::string imagePath = stem + ".png";
    {
        std::ofstream out(scriptPath);
        out << "set terminal pngcairo size " << width << "," << height << " font 'sans,11'\n";
        out << "set output '" << imagePath << "'\n";
        out << script << "\nunset output\n";
    }
    const std::string command = "gnuplot '" + scriptPath + "' 2>&1";
    FILE* pipe = ::popen(command.c_str(), "r");
    if (!pipe)
    {
        std::filesystem::remove(scriptPath);
        throw std::runtime_error("cannot start gnuplot (install gnuplot-nox)");
    }
    std::string messages;
    char buffer[256];
    while (std::fgets(buffer, sizeof(buffer), pipe))
    {
        messages += buffer;
    }
    const int status = ::pclose(pipe);
    std::filesystem::remove(scriptPath);
    if (status != 0 || !std::filesystem::exists(imagePath))
    {
        std::filesystem::remove(imagePath);
        throw std::runtime_error("gnuplot failed drawing " + pngPath + (messages.empty() ? "" : ": " + messages));
    }
    std::filesystem::rename(imagePath, pngPath); // atomic: the PNG appears whole or not at all
}
} // namespace masse::scene
