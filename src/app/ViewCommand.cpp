/// `masse view [SCENE]`: the interactive viewer (a window on a running scene), and its headless uses under Xvfb:
/// a screenshot after N frames or an event, and a frame-rate benchmark.

#include "Commands.h"
#include "SceneOptions.h"

#include "core/InputError.h"
#include "scene/SceneFile.h"
#include "scene/reports/ThicknessSectionReport.h"
#include "viewer/ViewerApp.h"

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <cstdio>
#include <memory>
#include <stdexcept>

namespace masse::app
{
namespace
{
struct ViewCommandOptions
{
    std::string scene;
    std::string window = "1024x720";
    std::string view = "overview";
    std::string draw;   ///< "": the scene's own (see defaultDrawing)
    std::string scalar; ///< "": the scene's own
    bool hidePanel = false;
    bool noUi = false;
    viewer::ViewerOptions viewer;
    SceneOverrides overrides;
};

void parseWindowSize(const std::string& text, viewer::ViewerOptions& options)
{
    int width = 0;
    int height = 0;
    char extra = 0;
    if (std::sscanf(text.c_str(), "%dx%d%c", &width, &height, &extra) != 2 || width < 64 || height < 64 ||
        width > 8192 || height > 8192)
    {
        throw InputError("--window: expected WIDTHxHEIGHT in pixels, each 64..8192 (got '" + text + "')");
    }
    options.width = width;
    options.height = height;
}

void printBenchmark(const scene::SceneSpec& spec, const viewer::DrawSettings& draw, const viewer::ViewerReport& report)
{
    const LatticeSpec& lattice = spec.sheet.lattice;
    const Lattice built = buildLattice(lattice);
    const double wall = report.wallSeconds > 0 ? report.wallSeconds : 1e-9;
    const int measuredFrames = report.frames > 1 ? report.frames - 1 : report.frames;
    nlohmann::json line = {
        {"benchmark", "view"},
        {"scene", spec.name},
        {"structure", std::string(structureName(lattice.structure))},
        {"size",
         std::to_string(lattice.countX) + "x" + std::to_string(lattice.layers) + "x" + std::to_string(lattice.countZ)},
        {"masses", built.massCount()},
        {"springs", built.springCount()},
        {"integrator", std::string(integratorName(spec.time.integrator))},
        {"dt", spec.time.dt},
        {"draw", std::string(viewer::drawModeName(draw.mode))},
        {"scalar", draw.mode == viewer::DrawMode::Scalar ? nlohmann::json(draw.scalar) : nlohmann::json()},
        {"frames", report.frames},
        {"wall_seconds", report.wallSeconds},
        {"fps", measuredFrames / wall},
        {"steps", report.steps},
        {"steps_per_second", double(report.steps) / wall},
        {"sim_seconds", report.simSeconds},
        {"realtime_factor", report.simSeconds / wall},
        {"step_ms", report.steps > 0 ? 1000 * report.stepSeconds / double(report.steps) : 0.0},
        {"threads", "simulation apart from drawing"},
        {"draw_ms", 1000 * report.drawSeconds / report.frames},
        {"renderer", report.renderer},
        {"final_scene", report.finalScene},
        {"pick_applied_ms", report.pickMeasured ? nlohmann::json(1000 * report.pickAppliedSeconds) : nlohmann::json()},
        {"pick_applied_frames", report.pickMeasured ? nlohmann::json(report.pickAppliedFrames) : nlohmann::json()},
    };
    std::printf("%s\n", line.dump().c_str());
}

/// What the viewer draws when the command line does not say: a scene that forms a part (a forming pressure, or a
/// thickness section to report) opens on its wall thickness, h / h0 with the colour bar from 0 to 1, which is what a
/// forming engineer watches (and, as a closed surface, cheaper to draw than the masses and springs), or on the scalar
/// --scalar names; any other scene on its masses and springs, coloured by speed when switched to the scalar mode.
void defaultDrawing(const scene::SceneSpec& spec, ViewCommandOptions& options)
{
    const bool formsAPart = spec.material.enabled && (spec.forming.enabled || scene::sectionSettings(spec) != nullptr);
    if (options.draw.empty())
    {
        options.draw = formsAPart ? "scalar" : "masses";
    }
    if (options.scalar.empty())
    {
        options.scalar = formsAPart ? "thickness_ratio" : "speed";
    }
}

void runView(ViewCommandOptions& options)
{
    const std::string path = options.scene.empty() ? dataDirectory() + "/scenes/paper-drop.json" : options.scene;
    scene::SceneSpec spec = loadSceneWithOverrides(path, options.overrides);
    defaultDrawing(spec, options);
    viewer::ViewerOptions& viewer = options.viewer;
    parseWindowSize(options.window, viewer);
    try
    {
        viewer.view = viewer::parseViewPreset(options.view);
        viewer.draw.mode = viewer::parseDrawMode(options.draw);
    }
    catch (const InputError& e)
    {
        throw InputError(std::string("--") + e.what());
    }
    viewer.draw.scalar = options.scalar;
    viewer.source = scene::RunSource{path, options.overrides};
    viewer.showPanel = !options.hidePanel;
    viewer.showUi = !options.noUi;
    if (viewer.frames < 0 || viewer.stepsPerFrame < 0)
    {
        throw InputError("--frames and --steps-per-frame: must be >= 0");
    }
    if ((!viewer.screenshot.empty() || !viewer.regions.empty() || viewer.benchmark) && viewer.frames == 0 &&
        viewer.untilEvent.empty())
    {
        throw InputError("--screenshot, --regions and --benchmark need --frames N (or --until EVENT) to end the run");
    }

    const viewer::ViewerReport report = viewer::runViewer(spec, viewer);
    if (viewer.benchmark)
    {
        printBenchmark(spec, viewer.draw, report);
    }
    if (!viewer.untilEvent.empty() && !report.eventSeen)
    {
        throw std::runtime_error("view: the event '" + viewer.untilEvent + "' did not happen within " +
                                 std::to_string(report.frames) + " frames");
    }
}
} // namespace

void addViewCommand(CLI::App& app)
{
    auto options = std::make_shared<ViewCommandOptions>();
    CLI::App* command = app.add_subcommand("view", "Open the viewer on a scene (default: the paper's drop scene)");
    command->add_option("scene", options->scene, "Scene file (JSON)");
    command->add_option("--frames", options->viewer.frames, "Close after N frames (0: when the window is closed)");
    command->add_option("--steps-per-frame", options->viewer.stepsPerFrame,
                        "Take exactly K steps per frame instead of following the clock (repeatable captures)");
    command->add_option("--until", options->viewer.untilEvent,
                        "Close after the frame in which this event first happens: contact, contact:block, rest:sheet");
    command->add_option("--screenshot", options->viewer.screenshot, "Write the last frame as a PNG");
    command->add_option("--regions", options->viewer.regions,
                        "Write where the sheet and obstacles are in the last frame (JSON, pixels)");
    command->add_flag("--benchmark", options->viewer.benchmark,
                      "Print a JSON line: frames and steps per second, real-time factor");
    command->add_option("--window", options->window, "Window size WIDTHxHEIGHT (default 1024x720)");
    command->add_option("--view", options->view, "Initial view: overview, below (paper figure 8), left (figure 9)");
    command->add_option("--draw", options->draw,
                        "Draw mode: masses, surface, scalar (default: scalar thickness_ratio for a scene that forms a "
                        "part, masses otherwise)");
    command->add_option("--scalar", options->scalar,
                        "Scalar for --draw scalar: speed, strain, temperature, thickness, thickness_ratio");
    command->add_flag("--hide-panel", options->hidePanel, "Start with the panel hidden (Tab shows it)");
    command->add_flag("--no-ui", options->noUi, "Draw the scene alone: no panel, no HUD");
    command->add_flag("--paused", options->viewer.startPaused, "Start paused");
    command->add_flag("--compare", options->viewer.compare,
                      "Run Bullet's soft-body twin beside the sheet and draw it as a ghost (see masse compare)");
    command->add_option("--save-run", options->viewer.saveRunPath,
                        "Where \"save run\" (w, or the panel) writes the run as a scene file for masse run to replay "
                        "(default: SCENE-NAME.run.json in the current folder)");
    addThreadsOption(*command, options->overrides.engine);
    addSceneOverrides(*command, options->overrides);
    command->footer(
        "Mouse: left drag orbits, right drag pans, wheel or middle drag zooms, Ctrl or Shift + left drag "
        "pulls a mass.\nKeys: space run/pause, n step, r reset, 1 2 3 views (overview, from below, left), "
        "v starting view,\nm draw mode, p pick mode, f follow the sheet, Tab panel, q or Esc quit.\nForming: j/k plug "
        "down/up, h hold it, Alt + left drag moves it, u vacuum or pressure on/off, w save the run (replay it with "
        "masse run).\nWithout a display: "
        "xvfb-run -a masse view ... (see --screenshot, --benchmark).");
    command->callback([options] { runView(*options); });
}
} // namespace masse::app
