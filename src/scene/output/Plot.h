#pragma once
/// PNG plots drawn by gnuplot (Debian's gnuplot-nox), written atomically.

#include <future>
#include <string>
#include <vector>

namespace masse::scene
{
/// Runs a gnuplot script whose output terminal is set by this function (pngcairo, width x height); the script
/// refers to its output as nothing: plot commands only. Throws std::runtime_error if gnuplot fails or is missing.
void plotPng(const std::string& script, const std::string& pngPath, int width = 1000, int height = 700);

/// Plots drawn side by side. Each gnuplot runs on one core, and a forming run draws three: the thickness and
/// temperature maps (some 0.08 s each at 64x2x64) and the section (0.04 s). `add` starts each as soon as its data is
/// written, so they draw together on the machine's cores, and while the run writes its other files. `finish` waits for
/// them all and throws the first failure; a batch destroyed unfinished (an exception on the way) still waits for its
/// gnuplots, so none is left writing into a folder being removed.
class PlotBatch
{
public:
    PlotBatch() = default;
    PlotBatch(const PlotBatch&) = delete;
    PlotBatch& operator=(const PlotBatch&) = delete;
    ~PlotBatch();

    /// Starts drawing `script` into `pngPath` as plotPng would; `removeAfter` are files the script reads (its data),
    /// removed once it has drawn, whatever happens.
    void add(const std::string& script, const std::string& pngPath, int width = 1000, int height = 700,
             std::vector<std::string> removeAfter = {});
    /// Waits for every plot added; throws the first failure (std::runtime_error) once all have ended.
    void finish();

private:
    struct Drawing
    {
        std::future<void> done;
        std::vector<std::string> removeAfter;
    };
    std::vector<Drawing> m_drawing;
};
} // namespace masse::scene
