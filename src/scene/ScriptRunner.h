#pragma once
/// Plays a scene's script: each action fires at the start of the first frame at or after its time; a grab's target
/// follows its path smoothly, updated every substep.

#include "scene/SceneSpec.h"

#include "bridge/BulletEnvironment.h"

#include "core/StepHook.h"

#include <functional>
#include <memory>

namespace masse::scene
{
/// Receives events: a name ("grab", "release", "pin", "unpin", "gravity", "move"), the object concerned, a time.
using EventSink = std::function<void(const std::string& name, const std::string& object, Real time)>;

/// Carries out the actions on what the scene owns: the heat model's (heater, ambient, obstacle_temperature) and the
/// forming pressure's (pressure).
using SceneAction = std::function<void(const ScriptAction& action)>;

class ScriptRunner final : public StepHook
{
public:
    ScriptRunner(std::vector<ScriptAction> actions, const Lattice& lattice, bridge::BulletEnvironment& environment,
                 EventSink sink, SceneAction sceneAction = {});

    StageSet stages() const override { return {StepStage::BeforeFrame, StepStage::AfterSubstep}; }
    /// Fires the actions due at the frame's start, before its stability estimate and contact detection.
    void beforeFrame(MassSpringSystem& system, StepContext& context, Real time) override;
    /// Aims every grab's spring along its path.
    void afterSubstep(MassSpringSystem& system, StepContext& context, Real h, Real time) override;

    /// Actions that have not fired yet, in the order they will.
    std::vector<const ScriptAction*> pending() const;

    /// Adds an action between steps. It fires as a scene file's action at its time would: at the start of the first
    /// frame at or after it, after the actions already due then.
    void add(ScriptAction action);
    /// Points the grab labelled `label` (holding a mass, or due at `time`) anew, between steps: from where its target
    /// is at `time`, straight to `target`, reached `duration` s later (at once for 0), then held there. Returns false
    /// when no such grab exists.
    bool redirectGrab(MassSpringSystem& system, const std::string& label, const Vec3& target, Real time, Real duration);

    /// Labels of the grabs that hold a mass or are still to fire.
    std::vector<std::string> grabLabels() const;

    /// The mass a grab holds now, or -1 (for drawing).
    std::vector<std::pair<Index, UserSpringId>> activeGrabs() const;
    /// The grabs that fired at the start of the latest frame: a step the integrator cannot then take is their doing.
    const std::vector<const ScriptAction*>& grabsFiredThisFrame() const { return m_grabsFiredThisFrame; }

private:
    struct Grab
    {
        std::string label;
        UserSpringId spring;
        Index mass;
        ScriptAction* action; ///< its path, which redirectGrab may change
    };
    void fire(MassSpringSystem& system, ScriptAction& action, Real time);
    static void aim(UserSpring& spring, const ScriptAction& action, Real time);

    /// Each action on the heap: a grab keeps a pointer to its own while actions are added.
    std::vector<std::unique_ptr<ScriptAction>> m_actions;
    std::size_t m_next = 0;
    const Lattice& m_lattice;
    bridge::BulletEnvironment& m_environment;
    EventSink m_sink;
    SceneAction m_sceneAction;
    std::vector<Grab> m_grabs;
    std::vector<const ScriptAction*> m_grabsFiredThisFrame;
};

/// The action's name as a scene file writes it ("grab", "heater"...).
std::string actionName(ScriptAction::Kind kind);

/// The mass of the sheet nearest a point.
Index nearestMass(const Particles& particles, const Vec3& point);
} // namespace masse::scene
