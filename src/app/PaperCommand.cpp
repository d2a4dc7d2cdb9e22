/// `masse paper` (the Figure 18 report) and `masse demo` (the main job): the paper's drop experiment for the five
/// sheet sizes of Table 2; with a display, `masse demo` opens the viewer on the drop scene instead.

#include "Commands.h"
#include "SceneOptions.h"

#include "scene/PaperExperiment.h"
#include "scene/SceneFile.h"
#include "scene/output/AtomicFile.h"
#include "scene/output/OutputFolder.h"
#include "scene/output/Plot.h"
#include "viewer/Display.h"
#include "viewer/ViewerApp.h"

#include <CLI/CLI.hpp>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>

namespace masse::app
{
namespace
{
struct PaperOptions
{
    std::string scene;
    std::string out;
    std::vector<int> sizes = scene::paperSizes;
    bool force = false;
    SceneOverrides overrides;
};

std::string figure18Script(const std::string& csv)
{
    // Two panels: wall-clock time (the paper's Figure 18) and simulated time to each stage, against sheet size.
    return "set datafile separator ','\n"
           "set key top left\n"
           "set grid\n"
           "set multiplot layout 1,2 title 'MaSSE: the paper''s drop experiment (Figure 18 analogue)'\n"
           "set xlabel 'sheet size N (N x 2 x N TRiMM)'\n"
           "set ylabel 'wall-clock time to stage (ms)'\n"
           "set title 'wall clock'\n"
           "plot '" +
           csv +
           "' every ::1 using 1:($8*1000) with linespoints title 'first polyhedron', "
           "'' every ::1 using 1:($9*1000) with linespoints title 'second polyhedron', "
           "'' every ::1 using 1:($10*1000) with linespoints title 'floor', "
           "'' every ::1 using 1:($11*1000) with linespoints title 'rest'\n"
           "set ylabel 'simulated time to stage (s)'\n"
           "set title 'simulated'\n"
           "plot '" +
           csv +
           "' every ::1 using 1:4 with linespoints title 'first polyhedron', "
           "'' every ::1 using 1:5 with linespoints title 'second polyhedron', "
           "'' every ::1 using 1:6 with linespoints title 'floor', "
           "'' every ::1 using 1:7 with linespoints title 'rest'\n"
           "unset multiplot\n";
}

void runPaper(const PaperOptions& options, bool writeFiles)
{
    const std::string scenePath = options.scene.empty() ? dataDirectory() + "/scenes/paper-drop.json" : options.scene;
    scene::SceneSpec spec = loadSceneWithOverrides(scenePath, options.overrides);
    // Checked before the experiment runs; written only when it has finished.
    scene::OutputFolder folder(writeFiles ? options.out : std::string(), options.force);
    std::printf(
        "The paper's drop experiment (%s): a Table 1 TRiMM sheet falls onto two polyhedra, slides between them\n"
        "to the floor and comes to rest; %s integrator, dt = %g s.\n\n",
        scenePath.c_str(), std::string(integratorName(spec.time.integrator)).c_str(), spec.time.dt);
    const std::vector<scene::PaperRow> rows = scene::runPaperExperiment(
        spec, options.sizes,
        [](const scene::PaperRow& row) { std::fprintf(stderr, "  %dx2x%d done\n", row.size, row.size); });
    std::printf("%s", scene::paperTable(rows).c_str());
    bool allInOrder = true;
    for (const scene::PaperRow& row : rows)
    {
        allInOrder = allInOrder && row.inOrder;
    }
    if (writeFiles)
    {
        const std::string csv = folder.staging() + "/figure18.csv";
        scene::writeFileAtomically(csv, scene::paperCsv(rows));
        scene::plotPng(figure18Script(csv), folder.staging() + "/figure18.png", 1200, 500);
        folder.commit();
        std::printf("\nwrote %s/figure18.csv and %s/figure18.png\n", options.out.c_str(), options.out.c_str());
    }
    if (!allInOrder)
    {
        throw std::runtime_error("the four stages did not all come in the paper's order");
    }
}
} // namespace

void addPaperCommand(CLI::App& app)
{
    auto options = std::make_shared<PaperOptions>();
    CLI::App* command =
        app.add_subcommand("paper", "The paper's Figure 18: the drop experiment for the Table 2 sheet sizes");
    command->add_option("--out", options->out, "Output folder for figure18.csv and figure18.png")->required();
    command->add_flag("--force", options->force, "Replace an --out folder that already holds files");
    command->add_option("--scene", options->scene, "Drop scene (default: data/scenes/paper-drop.json)");
    command->add_option("--sizes", options->sizes, "Sheet sizes N (default 3,6,8,9,12)")->delimiter(',');
    addThreadsOption(*command, options->overrides.engine);
    addSceneOverrides(*command, options->overrides);
    command->callback([options] { runPaper(*options, true); });
}

void addDemoCommand(CLI::App& app)
{
    auto options = std::make_shared<PaperOptions>();
    auto headless = std::make_shared<bool>(false);
    CLI::App* command = app.add_subcommand(
        "demo", "The main job: the paper's drop scene, in the viewer when there is a display, otherwise (or with "
                "--headless) a table of its four stages for the Table 2 sizes");
    command->add_flag("--headless", *headless, "Print the table even when a display is available");
    command->add_option("--out", options->out,
                        "Headless: also write figure18.csv and the plot figure18.png into this folder");
    addThreadsOption(*command, options->overrides.engine);
    command->callback(
        [options, headless]
        {
            if (!*headless)
            {
                const viewer::DisplayConnection display;
                if (display.connected())
                {
                    scene::SceneSpec spec = scene::loadScene(dataDirectory() + "/scenes/paper-drop.json");
                    spec.engine = options->overrides.engine;
                    viewer::runViewer(spec, {});
                    return;
                }
            }
            runPaper(*options, !options->out.empty());
        });
}
} // namespace masse::app
