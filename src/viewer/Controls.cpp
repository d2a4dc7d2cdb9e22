#include "Controls.h"

#include "core/material/HeatSources.h"

#include <cmath>
#include <limits>

namespace masse::viewer
{
namespace
{
/// Pixels within which a click catches a mass.
constexpr Real pickTolerancePixels = 12;

/// Box around points: what the views frame.
struct Bounds
{
    Vec3 low = Vec3::Constant(std::numeric_limits<Real>::infinity());
    Vec3 high = Vec3::Constant(-std::numeric_limits<Real>::infinity());
    void add(const Vec3& p)
    {
        low = low.cwiseMin(p);
        high = high.cwiseMax(p);
    }
};
} // namespace

Vec3 sheetCentre(const std::vector<Vec3>& positions)
{
    Vec3 sum = Vec3::Zero();
    for (const Vec3& p : positions)
    {
        sum += p;
    }
    return positions.empty() ? sum : Vec3(sum / Real(positions.size()));
}

void Controls::setView(ViewPreset preset, const SceneSnapshot& snapshot)
{
    Bounds sheet;
    for (const Vec3& p : snapshot.positions)
    {
        sheet.add(p);
    }
    if (preset == ViewPreset::FromBelow)
    {
        // The paper's figure 8 looks up through the sheet itself.
        camera = presetCamera(preset, sheet.low, sheet.high, viewport.aspect());
        return;
    }
    Bounds all = sheet;
    for (const ObstacleShape& obstacle : snapshot.obstacles)
    {
        if (!obstacle.partOfRoom)
        {
            for (const Vec3& p : obstacle.vertices)
            {
                all.add(p);
            }
        }
    }
    // Heater panels too: what heats the sheet belongs in the picture.
    const scene::HeatSpec& heat = snapshot.spec->heat;
    if (heat.enabled)
    {
        for (const RadiantHeater& heater : heat.settings.heaters)
        {
            for (const Vec3& corner : heaterCorners(heater))
            {
                all.add(corner);
            }
        }
    }
    camera = presetCamera(preset, all.low, all.high, viewport.aspect());
}

void Controls::update(const SceneSnapshot& snapshot)
{
    process.update(snapshot);
    if (follow && !snapshot.positions.empty())
    {
        camera.target = sheetCentre(snapshot.positions);
    }
}

void Controls::handle(const InputEvent& event, const UiCapture& ui, const SceneSnapshot& snapshot,
                      const CommandSink& post)
{
    switch (event.kind)
    {
    case InputKind::MouseDown:
    case InputKind::MouseUp:
        onButton(event, ui, snapshot, post);
        break;
    case InputKind::MouseMove:
        onMotion(event.x, event.y, post);
        break;
    case InputKind::Wheel:
        if (!ui.mouse)
        {
            camera.zoom(event.wheel > 0 ? Real(0.9) : Real(1) / Real(0.9));
        }
        break;
    case InputKind::KeyDown:
        if (!ui.keys && !event.modifiers.ctrl && !event.modifiers.alt && event.key < specialKeyBase)
        {
            // Letters arrive as their upper-case slot; the keys are lower case.
            const bool letter = event.key >= 'A' && event.key <= 'Z';
            onKey(static_cast<unsigned char>(letter && !event.modifiers.shift ? event.key - 'A' + 'a' : event.key),
                  snapshot, post);
        }
        break;
    case InputKind::KeyUp:
    case InputKind::Character:
        break;
    }
}

void Controls::beginPick(int x, int y, const SceneSnapshot& snapshot, const CommandSink& post)
{
    const std::vector<Vec3>& positions = snapshot.positions;
    const Ray ray = rayThroughPixel(camera, viewport, x + Real(0.5), y + Real(0.5));
    const std::optional<MassPick> hit =
        pickNearestMass(positions, ray, camera.pixelSizeAtUnitDepth(viewport), pickTolerancePixels);
    if (!hit)
    {
        // Nothing under the cursor: the drag turns the view instead.
        m_drag = Drag::Orbit;
        return;
    }
    const Vec3 picked = positions[hit->mass];
    m_dragPlane = dragPlaneFacing(camera, picked);
    pick = std::pair<Index, Vec3>(hit->mass, picked);
    post([mass = hit->mass, picked](ViewerSession& session) { session.beginPick(mass, picked); });
    m_drag = Drag::Pick;
}

void Controls::beginPlugDrag(int x, int y, const SceneSnapshot& snapshot)
{
    const std::optional<std::size_t> plug = ProcessControls::steeredObstacle(snapshot);
    if (!plug)
    {
        m_drag = Drag::Orbit;
        return;
    }
    const ObstacleShape& obstacle = snapshot.obstacles[*plug];
    m_dragPlane = dragPlaneFacing(camera, obstacle.position);
    const std::optional<Vec3> grabbed =
        intersect(rayThroughPixel(camera, viewport, x + Real(0.5), y + Real(0.5)), m_dragPlane);
    if (!grabbed)
    {
        m_drag = Drag::Orbit;
        return;
    }
    process.beginDrag(obstacle, grabbed->y());
    m_drag = Drag::Plug;
}

void Controls::onButton(const InputEvent& event, const UiCapture& ui, const SceneSnapshot& snapshot,
                        const CommandSink& post)
{
    if (event.kind == InputKind::MouseUp)
    {
        if (m_drag == Drag::Pick)
        {
            pick.reset();
            post([](ViewerSession& session) { session.endPick(); });
        }
        m_drag = Drag::None;
        return;
    }
    if (ui.mouse)
    {
        return;
    }
    m_lastX = event.x;
    m_lastY = event.y;
    const bool pickModifier = event.modifiers.ctrl || event.modifiers.shift;
    if (event.button == 0 && event.modifiers.alt)
    {
        beginPlugDrag(event.x, event.y, snapshot);
    }
    else if (event.button == 0 && (pickMode || pickModifier))
    {
        beginPick(event.x, event.y, snapshot, post);
    }
    else if (event.button == 0)
    {
        m_drag = Drag::Orbit;
    }
    else if (event.button == 1)
    {
        m_drag = Drag::Pan;
    }
    else if (event.button == 2)
    {
        m_drag = Drag::Zoom;
    }
}

void Controls::onMotion(int x, int y, const CommandSink& post)
{
    const Real dx = x - m_lastX;
    const Real dy = y - m_lastY;
    m_lastX = x;
    m_lastY = y;
    switch (m_drag)
    {
    case Drag::Orbit:
        camera.orbit(dx, dy);
        break;
    case Drag::Pan:
        // Panning moves the target by hand: following would pull it straight back.
        follow = false;
        camera.pan(dx, dy, viewport);
        break;
    case Drag::Zoom:
        camera.zoom(std::exp(dy * Real(0.01)));
        break;
    case Drag::Plug:
        if (const std::optional<Vec3> target =
                intersect(rayThroughPixel(camera, viewport, x + Real(0.5), y + Real(0.5)), m_dragPlane))
        {
            process.dragTo(target->y(), post);
        }
        break;
    case Drag::Pick:
        if (const std::optional<Vec3> target =
                intersect(rayThroughPixel(camera, viewport, x + Real(0.5), y + Real(0.5)), m_dragPlane))
        {
            if (pick)
            {
                pick->second = *target;
            }
            post([target = *target](ViewerSession& session) { session.movePick(target); });
        }
        break;
    case Drag::None:
        break;
    }
}

void Controls::onKey(unsigned char key, const SceneSnapshot& snapshot, const CommandSink& post)
{
    switch (key)
    {
    case ' ':
        post([](ViewerSession& session) { session.setPaused(!session.paused()); });
        break;
    case 'n':
        post(
            [](ViewerSession& session)
            {
                session.setPaused(true);
                session.requestStep();
            });
        break;
    case 'r':
        post([](ViewerSession& session) { session.reset(); });
        break;
    case 'v':
        setView(m_startView, snapshot);
        break;
    case '1':
        setView(ViewPreset::Overview, snapshot);
        break;
    case '2':
        setView(ViewPreset::FromBelow, snapshot);
        break;
    case '3':
        setView(ViewPreset::ElevatedLeft, snapshot);
        break;
    case 'f':
        follow = !follow;
        break;
    case 'm':
        draw.mode = DrawMode((int(draw.mode) + 1) % 3);
        break;
    case 'p':
        pickMode = !pickMode;
        break;
    case '\t':
        panelVisible = !panelVisible;
        break;
    case 'j':
        process.nudge(snapshot, -1, post);
        break;
    case 'k':
        process.nudge(snapshot, +1, post);
        break;
    case 'h':
        process.stop(snapshot, post);
        break;
    case 'u':
        process.switchPressure(snapshot, post);
        break;
    case 'w':
        process.saveRun(snapshot, post);
        break;
    case 'q':
    case 27:
        quit = true;
        break;
    default:
        break;
    }
}
} // namespace masse::viewer
