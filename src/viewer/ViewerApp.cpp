#include "ViewerApp.h"

#include "Controls.h"
#include "Display.h"
#include "FramePacing.h"
#include "GlHeaders.h"
#include "ImGuiInput.h"
#include "InputEvents.h"
#include "Panel.h"
#include "Picking.h"
#include "RateMeter.h"
#include "ScreenLayout.h"
#include "ScreenRegions.h"
#include "Screenshot.h"
#include "SimulationThread.h"
#include "ViewerSession.h"

#include "core/InputError.h"
#include "scene/output/AtomicFile.h"

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
    /// One pass of the loop: take the latest snapshot and draw a frame when one is due (input waiting, the frame
    /// interval gone, or the last); returns false when the run should stop. The simulation runs on its own thread.
    bool tick();
    /// Draws the scene and the UI and swaps; the last frame is also captured.
    void drawFrame(bool last);
    bool eventSeen() const;
    void capture();
    /// --benchmark: a pick on the middle mass halfway through, timed until the simulation carries it out.
    void benchmarkPick();

    ViewerOptions m_options;
    MassScalarRegistry m_scalars;
    ViewerSession m_session; ///< the simulation thread's while it runs
    std::unique_ptr<SimulationThread> m_simulation;
    std::shared_ptr<const SceneSnapshot> m_snapshot; ///< what this frame draws
    std::unique_ptr<Renderer> m_renderer;
    Panel m_panel;
    Controls m_controls;
    RateMeter m_rates;
    FrameStats m_stats;
    InputQueue m_input;
    ScreenLayout m_layout; ///< the scene's view and the side column; the camera's viewport is the scene's

    int m_window = 0;
    bool m_windowOpen = false;
    bool m_imguiStarted = false;

    Clock::time_point m_start;
    Clock::time_point m_lastTick;
    Clock::time_point m_lastFrame;
    std::uint64_t m_drawnSequence = 0; ///< the snapshot the last frame showed
    std::uint64_t m_lastSteps = 0;
    Real m_lastSimTime = 0;
    std::uint64_t m_lastGeneration = 0;
    std::uint64_t m_pickTicket = 0; ///< the benchmark's pick, until the simulation has carried it out
    Clock::time_point m_pickPosted;
    int m_pickFrame = 0;
    ViewerReport m_report;
    Real m_simAtFirstFrame = 0;
    std::uint64_t m_stepsAtFirstFrame = 0;
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
    event.button = button == GLUT_LEFT_BUTTON     ? 0
                   : button == GLUT_RIGHT_BUTTON  ? 1
                   : button == GLUT_MIDDLE_BUTTON ? 2
                                                  : -1;
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
      m_controls(options.view, options.draw)
{
    if (!options.source.path.empty())
    {
        m_session.setSource(options.source);
    }
    m_controls.process.saveRunPath = options.saveRunPath;
    if (m_controls.draw.mode == DrawMode::Scalar && !m_scalars.find(m_controls.draw.scalar))
    {
        throw InputError("--scalar: unknown scalar '" + m_controls.draw.scalar + "' (expected " + m_scalars.names() +
                         ")");
    }
    if (m_controls.draw.mode == DrawMode::Scalar)
    {
        // A scalar the scene has no values of would only paint the sheet one colour: say so instead.
        const std::string missing = scalarMissingReason(m_session.scene(), m_controls.draw.scalar);
        if (!missing.empty())
        {
            std::string available;
            for (const MassScalar& scalar : m_scalars.all())
            {
                if (scalarMissingReason(m_session.scene(), scalar.name).empty())
                {
                    available += (available.empty() ? "" : ", ") + scalar.name;
                }
            }
            throw InputError("--scalar " + m_controls.draw.scalar + ": " + missing + " (this scene '" +
                             m_session.spec().name + "' can show " + available + ")");
        }
    }
    // As `masse run` does, before the run starts: a sheet too stiff for an explicit integrator at the scene's step
    // would otherwise only show as slow motion.
    if (const std::string warning = m_session.scene().substepWarning(); !warning.empty())
    {
        std::fprintf(stderr, "warning: %s\n", warning.c_str());
    }
    m_controls.panelVisible = options.showPanel;
    m_session.setPaused(options.startPaused);
    m_session.setPauseAtEnd(!options.benchmark);
    m_layout = screenLayout(options.width, options.height, options.showUi);
    m_controls.viewport = m_layout.sceneViewport();
    m_simulation =
        std::make_unique<SimulationThread>(m_session, m_scalars, options.stepsPerFrame == 0, options.computeBudget);
}

ViewerApp::~ViewerApp()
{
    m_simulation->stop();
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
    m_controls.setView(m_options.view, *m_snapshot);
}

void ViewerApp::onReshape(int width, int height)
{
    ImGui_ImplGLUT_ReshapeFunc(width, height);
    m_layout = screenLayout(width, height, m_options.showUi);
    m_controls.viewport = m_layout.sceneViewport();
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
    for (const scene::SceneEvent& event : m_snapshot->events)
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
    const Viewport window{m_layout.window.width, m_layout.window.height};
    if (!m_options.screenshot.empty())
    {
        writePng(m_options.screenshot, readFrame(window), window);
    }
    if (!m_options.regions.empty())
    {
        // The scene's view starts at the window's top-left corner, so its boxes are the window's too.
        nlohmann::json regions = screenRegions(*m_snapshot, m_controls.camera, m_controls.viewport);
        regions["width"] = window.width;
        regions["height"] = window.height;
        const ScreenRect& scene = m_layout.scene;
        regions["scene"] = {scene.x, scene.y, scene.right(), scene.bottom()};
        const ScreenRect& column = m_layout.column;
        regions["panel"] = column.width > 0 ? nlohmann::json{column.x, column.y, column.right(), column.bottom()}
                                            : nlohmann::json(nullptr);
        scene::writeFileAtomically(m_options.regions, regions.dump(2) + "\n");
    }
}

void ViewerApp::benchmarkPick()
{
    const std::vector<Vec3>& positions = m_snapshot->positions;
    if (positions.empty())
    {
        return;
    }
    const Index mass = positions.size() / 2;
    const Vec3 target = positions[mass] + Vec3(0, Real(0.05), 0);
    m_controls.pick = std::pair<Index, Vec3>(mass, target);
    m_pickPosted = Clock::now();
    m_pickFrame = m_report.frames;
    m_pickTicket = m_simulation->post([mass, target](ViewerSession& session) { session.beginPick(mass, target); });
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
    if (fixedSteps)
    {
        // Captures: exactly k steps a frame, waited for (the only wait on the simulation, for repeatable pictures).
        m_simulation->waitFor(m_simulation->postSteps(m_options.stepsPerFrame));
    }
    m_simulation->setScalar(m_controls.draw.mode == DrawMode::Scalar ? m_controls.draw.scalar : "");
    m_snapshot = m_simulation->latest();
    const SceneSnapshot& snapshot = *m_snapshot;
    if (snapshot.generation != m_lastGeneration)
    {
        // A new scene: its steps and time count from zero.
        m_lastGeneration = snapshot.generation;
        m_lastSimTime = snapshot.time;
        m_controls.pick.reset();
    }
    const int steps = int(snapshot.steps - m_lastSteps);
    const Real simSeconds = std::max(Real(0), snapshot.time - m_lastSimTime);
    m_lastSteps = snapshot.steps;
    m_lastSimTime = snapshot.time;
    m_report.steps = snapshot.steps;
    m_report.stepSeconds = snapshot.stepSeconds;
    if (m_pickTicket != 0 && snapshot.appliedTicket >= m_pickTicket)
    {
        m_report.pickAppliedSeconds = secondsBetween(m_pickPosted, start);
        m_report.pickAppliedFrames = m_report.frames - m_pickFrame;
        m_report.pickMeasured = true;
        m_pickTicket = 0;
        m_controls.pick.reset();
        m_simulation->post([](ViewerSession& session) { session.endPick(); });
    }

    m_report.eventSeen = eventSeen();
    const bool last =
        m_controls.quit || m_report.eventSeen || (m_options.frames > 0 && m_report.frames + 1 >= m_options.frames);
    // Frames at most every 1/30 s while the scene runs, and only for a new picture or input (FramePacing.h).
    FrameMoment moment;
    moment.mustDraw = fixedSteps || last || !m_input.empty() || m_report.frames == 0;
    moment.paused = snapshot.paused;
    moment.newPicture = snapshot.sequence != m_drawnSequence;
    moment.sinceLastFrame = secondsBetween(m_lastFrame, start);
    const bool draw = frameDue(moment);
    if (draw)
    {
        m_lastFrame = start;
        m_drawnSequence = snapshot.sequence;
        const Clock::time_point drawStart = Clock::now();
        drawFrame(last);
        m_report.drawSeconds += secondsBetween(drawStart, Clock::now());
        if (++m_report.frames == 1)
        {
            // The first frame includes opening the window; rates are measured from its end.
            m_firstFrameEnd = Clock::now();
            m_simAtFirstFrame = snapshot.time;
            m_stepsAtFirstFrame = snapshot.steps;
        }
        if (m_options.benchmark && m_report.frames == std::max(2, m_options.frames / 2) && !m_report.pickMeasured &&
            m_pickTicket == 0)
        {
            benchmarkPick();
        }
    }
    m_rates.add(wall, draw ? 1 : 0, steps, simSeconds, snapshot.behind);
    m_stats = {m_rates.framesPerSecond(), m_rates.stepsPerSecond(), m_rates.realTimeFactor(),
               m_rates.hasFigures(),      m_rates.fellBehind(),     m_options.stepsPerFrame};
    if (!draw)
    {
        // Nothing due: wait a little rather than spin a core the simulation or the rasteriser could use.
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
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
        const UiCapture ui{ImGui::GetIO().WantCaptureMouse, ImGui::IsAnyItemActive()};
        const CommandSink post = [this](SessionCommand command) { m_simulation->post(std::move(command)); };
        for (const InputEvent& event : batch)
        {
            m_controls.handle(event, ui, *m_snapshot, post);
        }
        if (pass == 0)
        {
            m_controls.update(*m_snapshot);
        }
        if (m_options.showUi)
        {
            m_panel.visible = m_controls.panelVisible;
            const PanelRequests requests =
                m_panel.draw(*m_snapshot, *m_simulation, m_controls.draw, m_controls.pickMode, m_controls.follow,
                             m_controls.process, m_stats, m_scalars, *m_renderer, m_layout.column);
            m_controls.panelVisible = m_panel.visible;
            if (requests.view)
            {
                m_controls.setView(*requests.view, *m_snapshot);
            }
        }
        ImGui::Render();
    }
    m_renderer->draw(*m_snapshot, m_controls.pick, m_controls.camera, m_controls.viewport, m_controls.draw);
    ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
    if (last)
    {
        capture();
    }
    glutSwapBuffers();
}

ViewerReport ViewerApp::run()
{
    m_simulation->start();
    m_snapshot = m_simulation->latest();
    openWindow();
    m_start = Clock::now();
    m_lastTick = m_start;
    m_firstFrameEnd = m_start;
    while (tick())
    {
        glutMainLoopEvent();
    }
    m_report.wallSeconds = secondsBetween(m_firstFrameEnd, Clock::now());
    m_simulation->stop();
    // The session is this thread's again.
    m_report.simSeconds = m_session.scene().time() - m_simAtFirstFrame;
    m_report.steps = m_report.steps - m_stepsAtFirstFrame;
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
