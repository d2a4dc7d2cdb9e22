#pragma once
/// The Dear ImGui side of the window, docked in the window's side column (ScreenLayout) so it never covers the sheet:
/// the HUD (time, rates, counts, latest events, errors) at the top, the colour bar when the sheet is coloured by a
/// scalar, and the control panel (run, load, view, and the scene's parameters, rebuilt on Apply) below them.

#include "Camera.h"
#include "MassScalars.h"
#include "ProcessControls.h"
#include "Renderer.h"
#include "SceneSnapshot.h"
#include "ScreenLayout.h"
#include "SimulationThread.h"

#include <optional>
#include <string>

namespace masse::viewer
{
/// The rates the HUD shows, measured by the window's loop.
struct FrameStats
{
    Real framesPerSecond = 0;
    Real stepsPerSecond = 0;
    Real realTimeFactor = 0;
    bool measured = false; ///< the rates cover at least one full window of time
    bool behind = false;   ///< the simulation could not keep real time during the last measurement
    int fixedSteps = 0;    ///< steps per frame when the loop ignores the clock (captures); 0 in real time
};

/// What the window should do after the panel was drawn.
struct PanelRequests
{
    std::optional<ViewPreset> view;
};

class Panel
{
public:
    /// Draws the panel (when shown) and the HUD; carries out run, load and rebuild requests on the session.
    /// Reads the snapshot only; what the user asks of the scene goes to the simulation thread as commands.
    /// `column`: where the panel goes (ScreenLayout::column).
    PanelRequests draw(const SceneSnapshot& snapshot, SimulationThread& simulation, DrawSettings& draw, bool& pickMode,
                       bool& follow, ProcessControls& process, const FrameStats& stats,
                       const MassScalarRegistry& scalars, const Renderer& renderer, const ScreenRect& column);

    bool visible = true; ///< the controls (Tab); the HUD and the colour bar stay

private:
    void drawControls(const SceneSnapshot& snapshot, SimulationThread& simulation, DrawSettings& draw, bool& pickMode,
                      bool& follow, ProcessControls& process, const MassScalarRegistry& scalars,
                      PanelRequests& requests);
    /// The colour map with its end values and unit, or why the sheet is grey.
    void drawColourBar(const SceneSnapshot& snapshot, const DrawSettings& draw, const MassScalarRegistry& scalars);
    void drawSceneEditor(const SceneSnapshot& snapshot, SimulationThread& simulation);
    /// The forming bench: the pressure, the plug, the heaters, the obstacles' and the air's temperatures (as recorded
    /// actions on the running scene), and saving the run.
    void drawProcessControls(const SceneSnapshot& snapshot, SimulationThread& simulation, ProcessControls& process);
    /// A live section through a line across the sheet the user drags: drawn on the sheet, its h/h0 plotted here.
    void drawSection(const SceneSnapshot& snapshot, SimulationThread& simulation);
    void drawHud(const SceneSnapshot& snapshot, const FrameStats& stats, const DrawSettings& draw,
                 const Renderer& renderer);

    bool m_sectionOn = false;
    int m_sectionAxis = 0;      ///< 0: along x (a line of constant z), 2: along z
    float m_sectionAt = 0;      ///< m, where the line crosses the other axis
    scene::SceneSpec m_pending; ///< the spec being edited, applied with Apply
    bool m_edited = false;
    std::uint64_t m_generation = ~std::uint64_t(0);
    std::string m_path;
};
} // namespace masse::viewer
