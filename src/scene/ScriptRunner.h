#pragma once
/// Plays a scene's script: each action fires at the start of the first frame at or after its time; a grab's target
/// follows its path smoothly, updated every substep.

#include "scene/SceneSpec.h"

#include "bridge/BulletEnvironment.h"

#include "core/StepHook.h"

#include <functional>

namespace masse::scene
{
/// Receives events: a name ("grab", "release", "pin", "unpin", "gravity", "move"), the object concerned, a time.
using EventSink = std::function<void(const std::string& name, const std::string& object, Real time)>;

/// Carries out the actions on heat (heater, ambient), which the scene owns.
using HeatAction = std::function<void(const ScriptAction& action)>;

class ScriptRunner final : public StepHook
{
public:
    ScriptRunner(std::vector<ScriptAction> actions, const Lattice& lattice, bridge::BulletEnvironment& environment,
                 EventSink sink, HeatAction heat = {});

    /// Fires the actions due at the frame's start, before its stability estimate and contact detection.
    void beforeFrame(MassSpringSystem& system, StepContext& context, Real time) override;
    /// Aims every grab's spring along its path.
    void afterSubstep(MassSpringSystem& system, StepContext& context, Real h, Real time) override;

    /// Actions that have not fired yet, in the order they will.
    std::vector<const ScriptAction*> pending() const;

    /// The mass a grab holds now, or -1 (for drawing).
    std::vector<std::pair<Index, UserSpringId>> activeGrabs() const;

private:
    struct Grab
    {
        std::string label;
        UserSpringId spring;
        Index mass;
        const ScriptAction* action;
    };
    void fire(MassSpringSystem& system, const ScriptAction& action, Real time);
    static void aim(UserSpring& spring, const ScriptAction& action, Real time);

    std::vector<ScriptAction> m_actions;
    std::size_t m_next = 0;
    const Lattice& m_lattice;
    bridge::BulletEnvironment& m_environment;
    EventSink m_sink;
    HeatAction m_heat;
    std::vector<Grab> m_grabs;
};

/// The action's name as a scene file writes it ("grab", "heater"...).
std::string actionName(ScriptAction::Kind kind);

/// The mass of the sheet nearest a point.
Index nearestMass(const Particles& particles, const Vec3& point);
} // namespace masse::scene
