#pragma once
/// What the viewer does to its scene, apart from drawing: loading and rebuilding it (keeping the previous scene when
/// a new one fails), running it in real time, pausing and single steps, and the mouse's pick spring. No GL, so the
/// tests drive it as the window does.

#include "PickSpring.h"
#include "StepScheduler.h"

#include "scene/SavedRun.h"
#include "scene/Scene.h"
#include "scene/compare/Comparison.h"
#include "scene/reports/ThicknessSectionReport.h"

#include <memory>
#include <optional>
#include <string>

namespace masse::viewer
{
/// What one frame's advance did.
struct Advance
{
    int steps = 0;
    Real simSeconds = 0;  ///< simulated time advanced
    Real stepSeconds = 0; ///< wall time spent stepping
    bool behind = false;  ///< time owed to the simulation was dropped: it cannot keep real time (slow motion)
};

class ViewerSession
{
public:
    /// Builds the first scene; throws InputError for a spec that cannot be built (on the command line that is bad
    /// input; later failures keep the scene shown). With `compare`, the scene runs beside its Bullet soft-body twin
    /// (scene::Comparison), which the window draws as a ghost.
    explicit ViewerSession(scene::SceneSpec spec, bool compare = false);
    /// The comparison when the session runs one (--compare), else nullptr.
    const scene::Comparison* comparison() const { return m_comparison.get(); }

    scene::Scene& scene() { return *m_scene; }
    const scene::Scene& scene() const { return *m_scene; }
    const scene::SceneSpec& spec() const { return m_scene->spec(); }
    /// Bumped whenever a new scene replaces the old (its topology may differ: the renderer rebuilds its buffers).
    std::uint64_t generation() const { return m_generation; }

    /// Loads a scene file. On failure the current scene stays and error() holds the file's own message.
    bool load(const std::string& path);
    /// Builds a scene from a changed spec (the panel's edits). On failure the current scene stays.
    bool rebuild(const scene::SceneSpec& spec);
    /// Starts the current scene again (on failure, as rebuild).
    void reset();
    /// The last failure of a load, rebuild or step, for the window to show; "" when there is none.
    const std::string& error() const { return m_error; }
    void clearError() { m_error.clear(); }
    /// Set when the run reached its end (duration, or rest when the scene stops at rest) and the session paused.
    const std::string& notice() const { return m_notice; }

    bool paused() const { return m_paused; }
    void setPaused(bool paused);
    /// One step at the next advance, paused or not.
    void requestStep() { ++m_stepRequests; }
    /// Pause once when the scene's run is over (on by default; a benchmark runs on).
    void setPauseAtEnd(bool pause) { m_pauseAtEnd = pause; }

    /// Real time: banks wallSeconds and takes the steps owed while less than computeBudgetSeconds of wall time has
    /// gone (at least one step when one is owed and the budget is not zero).
    Advance advance(Real wallSeconds, Real computeBudgetSeconds);
    /// Exactly `steps` steps, whatever the clock says (deterministic captures); none while paused.
    Advance advanceSteps(int steps);

    /// Starts pulling `mass` toward `target` with a pick spring (replacing any earlier pick).
    void beginPick(Index mass, const Vec3& target);
    void movePick(const Vec3& target);
    void endPick();
    std::optional<Index> pickedMass() const;
    std::optional<Vec3> pickTarget() const;
    /// The live section the snapshots carry (the panel's), or none.
    void setSection(std::optional<scene::SectionSettings> section) { m_section = section; }
    const std::optional<scene::SectionSettings>& section() const { return m_section; }
    /// The mouse pulled a mass since the scene started: a saved run cannot replay that pull.
    bool mousePulled() const { return m_mousePulled; }

    /// Where the scene came from, for "save run": the command's file and flags, or the file load() read. A scene
    /// rebuilt from the panel's edits has none (nothing on disk describes it).
    void setSource(scene::RunSource source) { m_source = std::move(source); }
    const std::optional<scene::RunSource>& source() const { return m_source; }
    /// Adds a process action (a pressure, a steer, a heater, a temperature) at the scene's time: it fires at the start
    /// of the next frame, and a saved run holds it. False, with error() saying why, when the scene refuses it.
    bool act(scene::ScriptAction action);
    /// Writes the run so far to `path` as a scene file that `masse run` replays bit for bit (scene/SavedRun.h), and
    /// says so in notice() and on standard output (time, actions, state hash); false, with error(), when it cannot.
    bool saveRun(const std::string& path);

private:
    /// Builds a scene (or a comparison) from a spec and makes it current; throws what building throws.
    void replaceScene(scene::SceneSpec spec);
    /// replaceScene, a failure kept in error() (the current scene stays); false then.
    bool tryReplaceScene(const scene::SceneSpec& spec);
    /// One step, catching a diverged or refused step: the session pauses and reports it instead of dying.
    bool stepOnce(Advance& advance);
    void noticeEnd();

    bool m_compare = false;
    std::unique_ptr<scene::Scene> m_ownedScene;
    std::unique_ptr<scene::Comparison> m_comparison;
    scene::Scene* m_scene = nullptr; ///< m_ownedScene's, or m_comparison's
    std::uint64_t m_generation = 0;
    StepScheduler m_scheduler;
    bool m_paused = false;
    int m_stepRequests = 0;
    bool m_pauseAtEnd = true;
    bool m_endNoticed = false;
    std::string m_error;
    std::string m_notice;
    std::optional<UserSpringId> m_pick;
    Index m_pickedMass = 0;
    Vec3 m_pickTarget = Vec3::Zero();
    bool m_mousePulled = false;
    std::optional<scene::RunSource> m_source;
    std::optional<scene::SectionSettings> m_section;
};
} // namespace masse::viewer
