// Plots drawn side by side (PlotBatch): every plot of a batch is drawn, its data removed once drawn, and a plot that
// fails is reported after the others have ended, leaving no PNG of its own.

#include "support/TempFolder.h"

#include "scene/output/Plot.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

using namespace masse::scene;
namespace fs = std::filesystem;

namespace
{
fs::path freshFolder(const std::string& name)
{
    return masse::test::freshTempFolder("plot-batch-" + name);
}

/// A data file of a line, and the script that plots it.
std::string lineData(const fs::path& path)
{
    std::ofstream out(path);
    out << "0 0\n1 1\n2 4\n";
    return "plot '" + path.string() + "' using 1:2 with lines\n";
}

bool isPng(const fs::path& path)
{
    std::ifstream in(path, std::ios::binary);
    char signature[8] = {};
    in.read(signature, sizeof signature);
    return in && std::string(signature + 1, 3) == "PNG";
}
} // namespace

TEST(PlotBatch, DrawsEveryPlotAndRemovesTheirData)
{
    const fs::path folder = freshFolder("draws");
    PlotBatch plots;
    for (int k = 0; k < 3; ++k)
    {
        const fs::path data = folder / ("line" + std::to_string(k) + ".dat");
        plots.add(lineData(data), (folder / ("line" + std::to_string(k) + ".png")).string(), 200, 150, {data.string()});
    }
    plots.finish();
    for (int k = 0; k < 3; ++k)
    {
        EXPECT_TRUE(isPng(folder / ("line" + std::to_string(k) + ".png"))) << k;
        EXPECT_FALSE(fs::exists(folder / ("line" + std::to_string(k) + ".dat"))) << k;
    }
    // Nothing else is left beside them: no script, no half-drawn image.
    EXPECT_EQ(std::distance(fs::directory_iterator(folder), fs::directory_iterator()), 3);
}

TEST(PlotBatch, AFailingPlotIsReportedOnceTheOthersAreDrawn)
{
    const fs::path folder = freshFolder("fails");
    PlotBatch plots;
    const fs::path data = folder / "good.dat";
    plots.add("plot 'no-such-file-for-plot-batch.dat' using 1:2\n", (folder / "bad.png").string(), 200, 150);
    plots.add(lineData(data), (folder / "good.png").string(), 200, 150, {data.string()});
    try
    {
        plots.finish();
        FAIL() << "a plot of a missing file was drawn";
    }
    catch (const std::runtime_error& error)
    {
        EXPECT_NE(std::string(error.what()).find("bad.png"), std::string::npos) << error.what();
    }
    EXPECT_FALSE(fs::exists(folder / "bad.png"));
    EXPECT_TRUE(isPng(folder / "good.png"));
    EXPECT_FALSE(fs::exists(data));
}

TEST(PlotBatch, ABatchLeftUnfinishedWaitsForItsPlotsAndRemovesTheirData)
{
    const fs::path folder = freshFolder("unfinished");
    const fs::path data = folder / "line.dat";
    {
        PlotBatch plots;
        plots.add(lineData(data), (folder / "line.png").string(), 200, 150, {data.string()});
    } // as when an exception leaves the run before its plots are finished
    EXPECT_FALSE(fs::exists(data));
    // The drawing has ended: whatever it left does not change any more, and no temporary is left.
    for (const fs::directory_entry& entry : fs::directory_iterator(folder))
    {
        EXPECT_EQ(entry.path().filename(), "line.png") << entry.path();
    }
}
