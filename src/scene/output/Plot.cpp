#include "scene/output/Plot.h"

#include "scene/output/AtomicFile.h"

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <system_error>
#include <unistd.h>

namespace masse::scene
{
namespace
{
/// Removes `paths`, those that exist (a plot's data, whatever became of the plot).
void removeAll(const std::vector<std::string>& paths)
{
    for (const std::string& path : paths)
    {
        std::error_code ignored;
        std::filesystem::remove(path, ignored);
    }
}
} // namespace

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

PlotBatch::~PlotBatch()
{
    for (Drawing& drawing : m_drawing)
    {
        // A plot left deferred (no thread could be started for it) is not drawn for a run that is failing.
        if (drawing.done.wait_for(std::chrono::seconds(0)) != std::future_status::deferred)
        {
            drawing.done.wait();
        }
        removeAll(drawing.removeAfter);
    }
}

void PlotBatch::add(const std::string& script, const std::string& pngPath, int width, int height,
                    std::vector<std::string> removeAfter)
{
    Drawing drawing;
    drawing.removeAfter = std::move(removeAfter);
    // Drawn on a thread of its own, or when finished if no thread can be started (libstdc++ falls back to deferred).
    drawing.done =
        std::async(std::launch::async | std::launch::deferred, [=] { plotPng(script, pngPath, width, height); });
    m_drawing.push_back(std::move(drawing));
}

void PlotBatch::finish()
{
    std::exception_ptr firstFailure;
    for (Drawing& drawing : m_drawing)
    {
        try
        {
            drawing.done.get();
        }
        catch (...)
        {
            if (!firstFailure)
            {
                firstFailure = std::current_exception();
            }
        }
        removeAll(drawing.removeAfter);
    }
    m_drawing.clear();
    if (firstFailure)
    {
        std::rethrow_exception(firstFailure);
    }
}
} // namespace masse::scene
