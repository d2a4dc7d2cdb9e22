#pragma once
/// The viewer's window: freeglut, the renderer and the panel, the mouse and keys, and the frame loop that runs the
/// scene in real time (or a fixed number of steps a frame, for captures) and can stop after a number of frames or
/// an event to write a screenshot and print benchmark figures.

#include "Camera.h"
#include "MassScalars.h"
#include "Renderer.h"

#include "scene/SavedRun.h"
#include "scene/SceneSpec.h"

#include <string>

namespace masse::viewer
{
struct ViewerOptions
{
    int frames = 0;         ///< stop after this many frames (0: when the window is closed)
    int stepsPerFrame = 0;  ///< 0: real time; k > 0: exactly k steps every frame, whatever the clock says
    std::string untilEvent; ///< stop after the frame in which this event first happened: "contact", "contact:block"
    std::string screenshot; ///< PNG of the last frame
    std::string regions;    ///< JSON of where the sheet and obstacles are in the last frame (ScreenRegions.h)
    bool benchmark = false; ///< measure rates and run on past the scene's end
    int width = 1024;       ///< px, of the window
    int height = 720;
    ViewPreset view = ViewPreset::Overview;
    DrawSettings draw;
    bool showPanel = true;
    bool showUi = true; ///< false: the scene alone, no panel or HUD (clean screenshots)
    bool startPaused = false;
    bool compare = false;      ///< run Bullet's soft-body twin beside the sheet and draw it as a ghost
    Real computeBudget = 0.05; ///< s of stepping per pass of the loop at most; the rest stays owed to later passes
    scene::RunSource source;   ///< the scene's file and flags, for "save run" (no path: the run cannot be saved)
    std::string saveRunPath;   ///< where "save run" writes ("": <scene name>.run.json in the current folder)
};

/// What a run of the window did (the benchmark's figures).
struct ViewerReport
{
    int frames = 0;
    std::uint64_t steps = 0;
    Real wallSeconds = 0;   ///< from the end of the first frame (which includes opening the window) to the last
    Real simSeconds = 0;    ///< simulated over the same frames
    Real stepSeconds = 0;   ///< wall time spent stepping the scene (on the simulation thread)
    Real drawSeconds = 0;   ///< wall time spent drawing (scene, panel, swap)
    std::string renderer;   ///< GL_RENDERER
    std::string version;    ///< GL_VERSION
    bool eventSeen = false; ///< the `untilEvent` happened
    std::string finalScene; ///< the name of the scene shown when the window closed (one loaded from the panel)
    /// --benchmark's pick, posted halfway: wall seconds and frames drawn until the simulation thread carried it out
    /// (the window draws the pick spring from its own state in the next frame).
    bool pickMeasured = false;
    Real pickAppliedSeconds = 0;
    int pickAppliedFrames = 0;
};

/// Opens the window on the scene and runs until it is closed (or the options' frame count or event). Throws
/// InputError for a scene that does not build or when there is no display (before any window is opened).
ViewerReport runViewer(scene::SceneSpec spec, const ViewerOptions& options,
                       MassScalarRegistry scalars = standardMassScalars());
} // namespace masse::viewer
