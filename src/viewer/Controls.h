#pragma once
/// What the mouse and keys do to the view and the scene, apart from the panel: orbit, pan and zoom the camera, pick
/// and pull a mass, the view presets, following the sheet, and the run keys (pause, step, reset) as commands for the
/// simulation thread. No GL and no ImGui: the window tells it what ImGui took, and the tests drive it with events.

#include "Camera.h"
#include "InputEvents.h"
#include "Picking.h"
#include "ProcessControls.h"
#include "SceneGeometry.h"
#include "SceneSnapshot.h"
#include "SimulationThread.h"

#include <functional>
#include <optional>
#include <utility>

namespace masse::viewer
{
/// Where commands for the session go (the simulation thread's queue; a test's own list).
using CommandSink = std::function<void(SessionCommand)>;

/// What ImGui took of the input this frame.
struct UiCapture
{
    bool mouse = false; ///< the cursor is over the panel or a widget holds the mouse
    bool keys = false;  ///< a widget is active (a text field being typed into)
};

class Controls
{
public:
    Controls(ViewPreset startView, const DrawSettings& drawSettings) : draw(drawSettings), m_startView(startView) {}

    /// One event, after ImGui had it; `snapshot` is what the window shows now.
    void handle(const InputEvent& event, const UiCapture& ui, const SceneSnapshot& snapshot, const CommandSink& post);
    /// Frames a preset view on the snapshot: the sheet, the polyhedra and the heaters (from below: the sheet alone).
    void setView(ViewPreset preset, const SceneSnapshot& snapshot);
    /// Once a frame: keeps the camera's target on the sheet's centre while following.
    void update(const SceneSnapshot& snapshot);

    OrbitCamera camera;
    Viewport viewport;
    DrawSettings draw;
    bool pickMode = false;
    bool follow = false; ///< the camera's target follows the sheet's centre
    bool panelVisible = true;
    bool quit = false;
    /// The forming bench's controls, which the keys j, k, h, u and w reach too.
    ProcessControls process;
    /// The window's pick (mass, target): drawn at once, before the simulation thread has it.
    std::optional<std::pair<Index, Vec3>> pick;

private:
    enum class Drag
    {
        None,
        Orbit,
        Pan,
        Zoom,
        Pick,
        Plug, ///< Alt + left drag: the steered obstacle up and down after the cursor (ProcessControls::dragTo)
    };
    void onButton(const InputEvent& event, const UiCapture& ui, const SceneSnapshot& snapshot, const CommandSink& post);
    void onMotion(int x, int y, const CommandSink& post);
    void onKey(unsigned char key, const SceneSnapshot& snapshot, const CommandSink& post);
    void beginPick(int x, int y, const SceneSnapshot& snapshot, const CommandSink& post);
    /// Alt + left drag: from the steered obstacle, if the scene has one (else the drag orbits).
    void beginPlugDrag(int x, int y, const SceneSnapshot& snapshot);

    ViewPreset m_startView;
    Drag m_drag = Drag::None;
    int m_lastX = 0;
    int m_lastY = 0;
    DragPlane m_dragPlane;
};

/// The mean position of the sheet's masses (the point the camera follows).
Vec3 sheetCentre(const std::vector<Vec3>& positions);
} // namespace masse::viewer
