#include "ViewerApp.h"

#include "Display.h"
#include "DrawPacer.h"
#include "GlHeaders.h"
#include "ImGuiInput.h"
#include "InputEvents.h"
#include "Panel.h"
#include "Picking.h"
#include "RateMeter.h"
#include "ScreenRegions.h"
#include "Screenshot.h"
#include "ViewerSession.h"

#include "core/InputError.h"
#include "scene/AtomicFile.h"

#include <GL/freeglut.h>
#include <imgui.h>
#include <imgui_impl_glut.h>
#include <imgui_impl_opengl3.h>

#include <chrono>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <limits>
#include <memory>
#include <thread>
#include <utility>

namespace masse::viewer
{
namespace
{
using Clock = std::chrono::steady_clock;

Real secondsBetween(Clock::time_point from, Clock::time_point to)
{
    return std::chrono::duration<Real>(to - from).count();
}

/// Pixels within which a click catches a mass.
constexpr Real pickTolerancePixels = 12;

enum class Drag
{
    None,
    Orbit,
    Pan,
    Zoom,
    Pick,
};

/// Box around the current sheet and the scene's polyhedra (not the room): what the views frame.
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

class ViewerApp
{
public:
    ViewerApp(scene::SceneSpec spec, const ViewerOptions& options, MassScalarRegistry scalars);
    ~ViewerApp();
    ViewerReport run();

    /// GLUT callbacks (through the trampolines below) only queue the event; a frame takes its batch before NewFrame.
    void queue(const InputEvent& event) { m_input.push(event); }
    void onReshape(int width, int height);
    void onClose() { m_windowOpen = false; }

private:
    void openWindow();
    /// One pass of the loop: advance the scene, and draw a frame when one is due (the draw pacer) or it is the
    /// last; returns false when the run should stop.
    bool tick();
    /// Draws the scene and the UI and swaps; the last frame is also captured.
    void drawFrame(bool last);
    bool eventSeen() const;
    void setView(ViewPreset preset);
    void beginPick(int x, int y);
    void capture();
    /// The window's own response to an event ImGui has already been given (camera, pick, keys).
    void handle(const InputEvent& event);
    void onMouseButton(const InputEvent& event);
    void onMotion(int x, int y);
    void onKey(unsigned char key);

    ViewerOptions m_options;
    MassScalarRegistry m_scalars;
    ViewerSession m_session;
    std::unique_ptr<Renderer> m_renderer;
    Panel m_panel;
    DrawSettings m_draw;
    OrbitCamera m_camera;
    Viewport m_viewport;
    RateMeter m_rates;
    DrawPacer m_pacer;
    FrameStats m_stats;
    bool m_pickMode = false;
    InputQueue m_input;

    int m_window = 0;
    bool m_windowOpen = false;
    bool m_imguiStarted = false;
    bool m_quit = false;
    Drag m_drag = Drag::None;
    int m_lastX = 0;
    int m_lastY = 0;
    DragPlane m_dragPlane;

    Clock::time_point m_start;
    Clock::time_point m_lastTick;
    ViewerReport m_report;
    Real m_simAtFirstFrame = 0;
    Clock::time_point m_firstFrameEnd;
};

ViewerApp* g_app = nullptr;

/// Modifier keys GLUT reports as special keys (freeglut 3): their own events carry the state after them.
Modifiers modifiersNow(int specialKey = -1, bool down = false)
{
    const int held = glutGetModifiers();
    Modifiers m{(held & GLUT_ACTIVE_CTRL) != 0, (held & GLUT_ACTIVE_SHIFT) != 0, (held & GLUT_ACTIVE_ALT) != 0};
    switch (specialKey)
    {
    case GLUT_KEY_CTRL_L:
    case GLUT_KEY_CTRL_R:
        m.ctrl = down;
        break;
    case GLUT_KEY_SHIFT_L:
    case GLUT_KEY_SHIFT_R:
        m.shift = down;
        break;
    case GLUT_KEY_ALT_L:
    case GLUT_KEY_ALT_R:
        m.alt = down;
        break;
    default:
        break;
    }
    return m;
}

void mouseTrampoline(int button, int state, int x, int y)
{
    InputEvent event;
    event.kind = state == GLUT_DOWN ? InputKind::MouseDown : InputKind::MouseUp;
    event.button = button == GLUT_LEFT_BUTTON ? 0 : button == GLUT_RIGHT_BUTTON ? 1 : button == GLUT_MIDDLE_BUTTON ? 2 : -1;
    event.x = x;
    event.y = y;
    event.modifiers = modifiersNow();
    if (event.button >= 0)
    {
        g_app->queue(event);
    }
}
void motionTrampoline(int x, int y)
{
    InputEvent event;
    event.kind = InputKind::MouseMove;
    event.x = x;
    event.y = y;
    g_app->queue(event);
}
void wheelTrampoline(int, int direction, int x, int y)
{
    InputEvent event;
    event.kind = InputKind::Wheel;
    event.wheel = direction > 0 ? 1 : -1;
    event.x = x;
    event.y = y;
    g_app->queue(event);
}
void keyTrampoline(unsigned char key, int x, int y)
{
    InputEvent event;
    event.kind = InputKind::KeyDown;
    event.key = characterKeySlot(key);
    event.x = x;
    event.y = y;
    event.modifiers = modifiersNow();
    g_app->queue(event);
    if (key >= 32)
    {
        event.kind = InputKind::Character;
        event.character = key;
        g_app->queue(event);
    }
}
void keyUpTrampoline(unsigned char key, int x, int y)
{
    InputEvent event;
    event.kind = InputKind::KeyUp;
    event.key = characterKeySlot(key);
    event.x = x;
    event.y = y;
    event.modifiers = modifiersNow();
    g_app->queue(event);
}
void specialTrampoline(int key, int x, int y)
{
    InputEvent event;
    event.kind = InputKind::KeyDown;
    event.key = specialKeyBase + key;
    event.x = x;
    event.y = y;
    event.modifiers = modifiersNow(key, true);
    g_app->queue(event);
}
void specialUpTrampoline(int key, int x, int y)
{
    InputEvent event;
    event.kind = InputKind::KeyUp;
    event.key = specialKeyBase + key;
    event.x = x;
    event.y = y;
    event.modifiers = modifiersNow(key, false);
    g_app->queue(event);
}
void reshapeTrampoline(int width, int height)
{
    g_app->onReshape(width, height);
}
void closeTrampoline()
{
    g_app->onClose();
}
/// The loop draws every frame itself; freeglut insists on a display callback all the same.
void displayNothing() {}

/// freeglut ends the process on a fatal error (no OpenGL 3.3, for one); say what the viewer needs first.
void glutFatal(const char* format, va_list arguments)
{
    std::fprintf(stderr, "masse: view: freeglut: ");
    std::vfprintf(stderr, format, arguments);
    std::fprintf(stderr, "\nmasse: the viewer needs OpenGL 3.3 core (Mesa's llvmpipe provides it under Xvfb)\n");
    std::exit(1);
}
} // namespace

ViewerApp::ViewerApp(scene::SceneSpec spec, const ViewerOptions& options, MassScalarRegistry scalars)
    : m_options(options), m_scalars(std::move(scalars)), m_session(std::move(spec), options.compare),
      m_draw(options.draw)
{
    if (m_draw.mode == DrawMode::Scalar && !m_scalars.find(m_draw.scalar))
    {
        throw InputError("--scalar: unknown scalar '" + m_draw.scalar + "' (expected " + m_scalars.names() + ")");
    }
    m_panel.visible = options.showPanel;
    m_session.setPaused(options.startPaused);
    m_session.setPauseAtEnd(!options.benchmark);
    m_viewport = {options.width, options.height};
}

ViewerApp::~ViewerApp()
{
    if (m_windowOpen)
    {
        // GL objects go while their context still exists.
        m_renderer.reset();
        ImGui_ImplOpenGL3_Shutdown();
        glutCloseFunc(nullptr);
        glutDestroyWindow(m_window);
    }
    if (m_imguiStarted)
    {
        ImGui_ImplGLUT_Shutdown();
        ImGui::DestroyContext();
        // freeglut would otherwise tidy up at exit, calling back into an app that no longer exists.
        glutExit();
    }
    g_app = nullptr;
}

void ViewerApp::openWindow()
{
    int argc = 1;
    char name[] = "masse";
    char* argv[] = {name, nullptr};
    glutInitErrorFunc(glutFatal);
    glutInit(&argc, argv);
    glutInitContextVersion(3, 3);
    glutInitContextProfile(GLUT_CORE_PROFILE);
    glutInitDisplayMode(GLUT_RGBA | GLUT_DOUBLE | GLUT_DEPTH);
    glutInitWindowSize(m_options.width, m_options.height);
    glutSetOption(GLUT_ACTION_ON_WINDOW_CLOSE, GLUT_ACTION_CONTINUE_EXECUTION);
    const std::string title = "MaSSE: " + m_session.spec().name;
    m_window = glutCreateWindow(title.c_str());
    m_windowOpen = true;

    IMGUI_CHECKVERSION();
    ImGui::CreateContext();
    m_imguiStarted = true;
    ImGui::GetIO().IniFilename = nullptr; // no imgui.ini left in the working folder
    ImGui::StyleColorsDark();
    ImGui_ImplGLUT_Init();
    mapImGuiKeys();
    ImGui_ImplOpenGL3_Init("#version 330 core");

    // Our callbacks queue every event; a frame gives its batch to ImGui first and acts on what ImGui does not want.
    glutDisplayFunc(displayNothing);
    glutReshapeFunc(reshapeTrampoline);
    glutMouseFunc(mouseTrampoline);
    glutMotionFunc(motionTrampoline);
    glutPassiveMotionFunc(motionTrampoline);
    glutMouseWheelFunc(wheelTrampoline);
    glutKeyboardFunc(keyTrampoline);
    glutKeyboardUpFunc(keyUpTrampoline);
    glutSpecialFunc(specialTrampoline);
    glutSpecialUpFunc(specialUpTrampoline);
    glutCloseFunc(closeTrampoline);

    m_renderer = std::make_unique<Renderer>();
    m_report.renderer = reinterpret_cast<const char*>(glGetString(GL_RENDERER));
    m_report.version = reinterpret_cast<const char*>(glGetString(GL_VERSION));
    onReshape(glutGet(GLUT_WINDOW_WIDTH), glutGet(GLUT_WINDOW_HEIGHT));
    setView(m_options.view);
}

void ViewerApp::setView(ViewPreset preset)
{
    scene::Scene& scene = m_session.scene();
    Bounds sheet;
    for (const Vec3& p : scene.system().particles.position)
    {
        sheet.add(p);
    }
    if (preset == ViewPreset::FromBelow)
    {
        // The paper's figure 8 looks up through the sheet itself.
        m_camera = presetCamera(preset, sheet.low, sheet.high, m_viewport.aspect());
        return;
    }
    Bounds all = sheet;
    for (int i = 0; i < scene.environment().obstacleCount(); ++i)
    {
        const bridge::Obstacle& obstacle = scene.environment().obstacle(i);
        if (!obstacle.partOfRoom)
        {
            for (const Vec3& p : obstacleVertices(obstacle))
            {
                all.add(p);
            }
        }
    }
    m_camera = presetCamera(preset, all.low, all.high, m_viewport.aspect());
}

void ViewerApp::onReshape(int width, int height)
{
    ImGui_ImplGLUT_ReshapeFunc(width, height);
    m_viewport = {std::max(1, width), std::max(1, height)};
}

void ViewerApp::beginPick(int x, int y)
{
    const std::vector<Vec3>& positions = m_session.scene().system().particles.position;
    const Ray ray = rayThroughPixel(m_camera, m_viewport, x + Real(0.5), y + Real(0.5));
    const std::optional<MassPick> hit =
        pickNearestMass(positions, ray, m_camera.pixelSizeAtUnitDepth(m_viewport), pickTolerancePixels);
    if (!hit)
    {
        // Nothing under the cursor: the drag turns the view instead.
        m_drag = Drag::Orbit;
        return;
    }
    const Vec3 picked = positions[hit->mass];
    m_dragPlane = dragPlaneFacing(m_camera, picked);
    m_session.beginPick(hit->mass, picked);
    m_drag = Drag::Pick;
}

void ViewerApp::handle(const InputEvent& event)
{
    const ImGuiIO& io = ImGui::GetIO();
    switch (event.kind)
    {
    case InputKind::MouseDown:
    case InputKind::MouseUp:
        onMouseButton(event);
        break;
    case InputKind::MouseMove:
        onMotion(event.x, event.y);
        break;
    case InputKind::Wheel:
        if (!io.WantCaptureMouse)
        {
            m_camera.zoom(event.wheel > 0 ? Real(0.9) : Real(1) / Real(0.9));
        }
        break;
    case InputKind::KeyDown:
        if (!ImGui::IsAnyItemActive() && !event.modifiers.ctrl && !event.modifiers.alt && event.key < specialKeyBase)
        {
            // Letters arrive as their upper-case slot; the keys are lower case.
            const int key = event.key >= 'A' && event.key <= 'Z' && !event.modifiers.shift ? event.key - 'A' + 'a'
                                                                                               : event.key;
            onKey(static_cast<unsigned char>(key));
        }
        break;
    case InputKind::KeyUp:
    case InputKind::Character:
        break;
    }
}

void ViewerApp::onMouseButton(const InputEvent& event)
{
    if (event.kind == InputKind::MouseUp)
    {
        if (m_drag == Drag::Pick)
        {
            m_session.endPick();
        }
        m_drag = Drag::None;
        return;
    }
    if (ImGui::GetIO().WantCaptureMouse)
    {
        return;
    }
    m_lastX = event.x;
    m_lastY = event.y;
    const bool pickModifier = event.modifiers.ctrl || event.modifiers.shift;
    if (event.button == 0 && (m_pickMode || pickModifier))
    {
        beginPick(event.x, event.y);
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

void ViewerApp::onMotion(int x, int y)
{
    const Real dx = x - m_lastX;
    const Real dy = y - m_lastY;
    m_lastX = x;
    m_lastY = y;
    switch (m_drag)
    {
    case Drag::Orbit:
        m_camera.orbit(dx, dy);
        break;
    case Drag::Pan:
        m_camera.pan(dx, dy, m_viewport);
        break;
    case Drag::Zoom:
        m_camera.zoom(std::exp(dy * Real(0.01)));
        break;
    case Drag::Pick:
        if (const std::optional<Vec3> target =
                intersect(rayThroughPixel(m_camera, m_viewport, x + Real(0.5), y + Real(0.5)), m_dragPlane))
        {
            m_session.movePick(*target);
        }
        break;
    case Drag::None:
        break;
    }
}

void ViewerApp::onKey(unsigned char key)
{
    switch (key)
    {
    case ' ':
        m_session.setPaused(!m_session.paused());
        break;
    case 'n':
        m_session.setPaused(true);
        m_session.requestStep();
        break;
    case 'r':
        m_session.reset();
        break;
    case 'v':
        setView(m_options.view);
        break;
    case '1':
        setView(ViewPreset::Overview);
        break;
    case '2':
        setView(ViewPreset::FromBelow);
        break;
    case '3':
        setView(ViewPreset::ElevatedLeft);
        break;
    case 'm':
        m_draw.mode = DrawMode((int(m_draw.mode) + 1) % 3);
        break;
    case 'p':
        m_pickMode = !m_pickMode;
        break;
    case '\t':
        m_panel.visible = !m_panel.visible;
        break;
    case 'q':
    case 27:
        m_quit = true;
        break;
    default:
        break;
    }
}

bool ViewerApp::eventSeen() const
{
    if (m_options.untilEvent.empty())
    {
        return false;
    }
    const std::string& wanted = m_options.untilEvent;
    const std::size_t colon = wanted.find(':');
    const std::string name = wanted.substr(0, colon);
    const std::string object = colon == std::string::npos ? "" : wanted.substr(colon + 1);
    for (const scene::SceneEvent& event : m_session.scene().events())
    {
        if (event.name == name && (object.empty() || event.object == object))
        {
            return true;
        }
    }
    return false;
}

void ViewerApp::capture()
{
    if (!m_options.screenshot.empty())
    {
        writePng(m_options.screenshot, readFrame(m_viewport), m_viewport);
    }
    if (!m_options.regions.empty())
    {
        scene::writeFileAtomically(m_options.regions,
                                   screenRegions(m_session.scene(), m_camera, m_viewport).dump(2) + "\n");
    }
}

bool ViewerApp::tick()
{
    if (!m_windowOpen)
    {
        return false;
    }
    const Clock::time_point start = Clock::now();
    const Real wall = secondsBetween(m_lastTick, start);
    m_lastTick = start;
    const bool fixedSteps = m_options.stepsPerFrame > 0;
    const Advance advance =
        fixedSteps ? m_session.advanceSteps(m_options.stepsPerFrame) : m_session.advance(wall, m_options.computeBudget);
    m_report.steps += std::uint64_t(advance.steps);
    m_report.stepSeconds += advance.stepSeconds;
    m_pacer.stepped(advance.steps, advance.stepSeconds, m_session.spec().time.dt);
    m_report.eventSeen = eventSeen();
    const bool last = m_quit || m_report.eventSeen || (m_options.frames > 0 && m_report.frames + 1 >= m_options.frames);
    const Real now = secondsBetween(m_start, start);
    const bool draw = fixedSteps || last || !m_input.empty() || m_pacer.due(now, !m_session.paused());
    if (draw)
    {
        const Clock::time_point drawStart = Clock::now();
        drawFrame(last);
        const Real cost = secondsBetween(drawStart, Clock::now());
        m_pacer.drew(now, cost);
        m_report.drawSeconds += cost;
        if (++m_report.frames == 1)
        {
            // The first frame includes opening the window; rates are measured from its end.
            m_firstFrameEnd = Clock::now();
            m_simAtFirstFrame = m_session.scene().time();
        }
    }
    m_rates.add(wall, draw ? 1 : 0, advance.steps, advance.simSeconds, advance.behind);
    m_stats = {m_rates.framesPerSecond(), m_rates.stepsPerSecond(), m_rates.realTimeFactor(),
               m_rates.hasFigures(),      m_rates.fellBehind(),     m_options.stepsPerFrame};
    if (!draw && advance.steps == 0)
    {
        // Nothing was due: wait a little rather than spin a core the simulation or the rasteriser could use.
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    return !last;
}

void ViewerApp::drawFrame(bool last)
{
    // ImGui sizes auto-resizing windows from the previous frame's contents; a captured frame is laid out twice so
    // a line added this frame (a new event in the HUD) is not clipped in the picture.
    const int uiPasses = last ? 2 : 1;
    for (int pass = 0; pass < uiPasses; ++pass)
    {
        // Input reaches ImGui before NewFrame, never between it and Render (ImGui 1.86 asserts on modifiers that
        // change mid-frame). The window acts after NewFrame, on what ImGui did not take as of this frame: a key typed
        // just after Enter left a text field is the window's, not the field's.
        const std::vector<InputEvent> batch = pass == 0 ? m_input.takeFrame() : std::vector<InputEvent>{};
        applyToImGui(batch);
        ImGui_ImplOpenGL3_NewFrame();
        ImGui_ImplGLUT_NewFrame();
        for (const InputEvent& event : batch)
        {
            handle(event);
        }
        if (m_options.showUi)
        {
            const PanelRequests requests = m_panel.draw(m_session, m_draw, m_pickMode, m_stats, m_scalars, *m_renderer);
            if (requests.view)
            {
                setView(*requests.view);
            }
        }
        ImGui::Render();
    }
    m_renderer->draw(m_session, m_camera, m_viewport, m_draw, m_scalars);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    if (last)
    {
        capture();
    }
    glutSwapBuffers();
}

ViewerReport ViewerApp::run()
{
    openWindow();
    m_start = Clock::now();
    m_lastTick = m_start;
    m_firstFrameEnd = m_start;
    while (tick())
    {
        glutMainLoopEvent();
    }
    m_report.wallSeconds = secondsBetween(m_firstFrameEnd, Clock::now());
    m_report.simSeconds = m_session.scene().time() - m_simAtFirstFrame;
    m_report.finalScene = m_session.spec().name;
    return m_report;
}

ViewerReport runViewer(scene::SceneSpec spec, const ViewerOptions& options, MassScalarRegistry scalars)
{
    if (g_app != nullptr)
    {
        throw std::logic_error("runViewer: one viewer at a time");
    }
    // Everything wrong with the input is reported before a window is opened, and the display is checked before
    // freeglut gets the chance to end the process over it.
    ViewerApp app(std::move(spec), options, std::move(scalars));
    const DisplayConnection display;
    display.require();
    g_app = &app;
    return app.run();
}
} // namespace masse::viewer
