#include "ViewerSession.h"

#include "core/Format.h"
#include "core/InputError.h"
#include "core/NumericalError.h"
#include "core/Simulator.h"
#include "scene/Runner.h"
#include "scene/SceneFile.h"
#include "scene/output/AtomicFile.h"

#include <chrono>
#include <cstdio>

namespace masse::viewer
{
namespace
{
Real secondsSince(std::chrono::steady_clock::time_point start)
{
    return std::chrono::duration<Real>(std::chrono::steady_clock::now() - start).count();
}

std::string formatTime(Real t)
{
    return formatNumber("%.3f", t);
}
} // namespace

ViewerSession::ViewerSession(scene::SceneSpec spec, bool compare) : m_compare(compare), m_scheduler(spec.time.dt)
{
    replaceScene(std::move(spec));
}

void ViewerSession::replaceScene(scene::SceneSpec spec)
{
    // Build first: on failure the current scene stays as it is.
    std::unique_ptr<scene::Comparison> comparison;
    std::unique_ptr<scene::Scene> owned;
    if (m_compare)
    {
        comparison = std::make_unique<scene::Comparison>(std::move(spec), scene::CompareOptions{});
    }
    else
    {
        owned = std::make_unique<scene::Scene>(std::move(spec));
    }
    // The pick spring lived in the old system; it goes with it.
    m_pick.reset();
    m_mousePulled = false;
    m_comparison = std::move(comparison);
    m_ownedScene = std::move(owned);
    m_scene = m_comparison ? &m_comparison->scene() : m_ownedScene.get();
    ++m_generation;
    m_scheduler.setStep(m_scene->spec().time.dt);
    m_scheduler.clear();
    m_endNoticed = false;
    m_notice.clear();
    m_error.clear();
}

bool ViewerSession::load(const std::string& path)
{
    try
    {
        scene::SceneSpec spec = scene::loadScene(path);
        spec.engine = m_scene->spec().engine; // the threads and estimate the viewer was started with
        replaceScene(std::move(spec));
        m_source = scene::RunSource{path, {}};
        return true;
    }
    catch (const std::exception& e)
    {
        m_error = e.what();
        return false;
    }
}

bool ViewerSession::tryReplaceScene(const scene::SceneSpec& spec)
{
    try
    {
        replaceScene(spec);
        return true;
    }
    catch (const std::exception& e)
    {
        m_error = e.what();
        return false;
    }
}

bool ViewerSession::rebuild(const scene::SceneSpec& spec)
{
    if (!tryReplaceScene(spec))
    {
        return false;
    }
    m_source.reset(); // edited in the panel: no file describes it
    return true;
}

void ViewerSession::reset()
{
    // A fresh scene from the same spec rather than Scene::reset, which tears the scene down before building it
    // again: should the build fail now (a mesh file gone since), the scene shown must survive.
    const scene::SceneSpec spec = m_scene->spec();
    tryReplaceScene(spec);
}

bool ViewerSession::act(scene::ScriptAction action)
{
    action.time = m_scene->time();
    try
    {
        m_scene->addAction(std::move(action));
        return true;
    }
    catch (const std::exception& e)
    {
        m_error = std::string("the action was refused: ") + e.what();
        return false;
    }
}

bool ViewerSession::saveRun(const std::string& path)
{
    if (!m_source)
    {
        m_error = "save run: this scene was changed in the panel, and only a scene read from a file can be saved "
                  "(load a file, or start the viewer on one)";
        return false;
    }
    try
    {
        const nlohmann::json document = scene::savedRunDocument(*m_source, m_scene->addedActions(), m_scene->time());
        scene::writeFileAtomically(path, document.dump(2) + "\n");
    }
    catch (const std::exception& e)
    {
        m_error = std::string("save run: ") + e.what();
        return false;
    }
    m_notice = "saved the run to " + path + ": t = " + formatTime(m_scene->time()) + " s, " +
               std::to_string(m_scene->addedActions().size()) + " action(s), state " + scene::stateHashText(*m_scene) +
               " (masse run replays it)" +
               (m_mousePulled ? "; the mouse's pulls are not in it, so the replay will differ" : "");
    std::printf("%s\n", m_notice.c_str());
    std::fflush(stdout);
    return true;
}

void ViewerSession::setPaused(bool paused)
{
    m_paused = paused;
    // Time that passes while paused is not owed to the simulation afterwards.
    m_scheduler.clear();
    if (!paused)
    {
        m_notice.clear();
    }
}

bool ViewerSession::stepOnce(Advance& advance)
{
    const Real before = m_scene->time();
    try
    {
        if (m_comparison)
        {
            m_comparison->step(); // the scene, then every twin the same frame
        }
        else
        {
            m_scene->step();
        }
    }
    catch (const NumericalError& e)
    {
        m_error = std::string("the simulation diverged: ") + e.what() +
                  " (reset, or rebuild with a smaller dt or the implicit integrator)";
        m_paused = true;
        return false;
    }
    catch (const InputError& e)
    {
        m_error = std::string("the step was refused: ") + e.what();
        m_paused = true;
        return false;
    }
    ++advance.steps;
    advance.simSeconds += m_scene->time() - before;
    noticeEnd();
    return true;
}

void ViewerSession::noticeEnd()
{
    if (!m_pauseAtEnd || m_endNoticed || !m_scene->finished())
    {
        return;
    }
    m_endNoticed = true;
    m_paused = true;
    const Real rest = m_scene->eventTime("rest", "sheet");
    m_notice = rest >= 0 ? "the sheet came to rest at t = " + formatTime(rest) + " s; the run is over (space runs on)"
                         : "the run reached its duration of " + formatTime(m_scene->spec().run.duration) +
                               " s (space runs on)";
}

Advance ViewerSession::advance(Real wallSeconds, Real computeBudgetSeconds)
{
    Advance advance;
    const auto start = std::chrono::steady_clock::now();
    for (; m_stepRequests > 0; --m_stepRequests)
    {
        if (!stepOnce(advance))
        {
            m_stepRequests = 0;
            break;
        }
    }
    if (!m_paused)
    {
        advance.behind = m_scheduler.addWallTime(wallSeconds);
        // Within the budget only: what is left stays owed for the next passes, so input and frames keep coming.
        while (!m_paused && m_scheduler.stepDue() && secondsSince(start) < computeBudgetSeconds)
        {
            if (!stepOnce(advance))
            {
                break;
            }
            m_scheduler.stepTaken();
        }
    }
    advance.stepSeconds = secondsSince(start);
    return advance;
}

Advance ViewerSession::advanceSteps(int steps)
{
    Advance advance;
    const auto start = std::chrono::steady_clock::now();
    const int wanted = (m_paused ? 0 : steps) + m_stepRequests;
    m_stepRequests = 0;
    for (int i = 0; i < wanted; ++i)
    {
        if (!stepOnce(advance))
        {
            break;
        }
    }
    advance.stepSeconds = secondsSince(start);
    return advance;
}

void ViewerSession::beginPick(Index mass, const Vec3& target)
{
    endPick();
    MassSpringSystem& system = m_scene->system();
    m_pick = system.userSprings.add(makePickSpring(system, mass, target));
    m_pickedMass = mass;
    m_pickTarget = target;
    m_mousePulled = true;
    system.markChanged();
}

void ViewerSession::movePick(const Vec3& target)
{
    if (!m_pick)
    {
        return;
    }
    if (UserSpring* spring = m_scene->system().userSprings.find(*m_pick))
    {
        spring->target = target;
        m_pickTarget = target;
    }
}

void ViewerSession::endPick()
{
    if (!m_pick)
    {
        return;
    }
    MassSpringSystem& system = m_scene->system();
    system.userSprings.remove(*m_pick);
    system.markChanged();
    m_pick.reset();
}

std::optional<Index> ViewerSession::pickedMass() const
{
    return m_pick ? std::optional<Index>(m_pickedMass) : std::nullopt;
}

std::optional<Vec3> ViewerSession::pickTarget() const
{
    return m_pick ? std::optional<Vec3>(m_pickTarget) : std::nullopt;
}
} // namespace masse::viewer
