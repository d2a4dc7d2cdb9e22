#include "scene/ScriptRunner.h"

#include "scene/Pins.h"

#include <algorithm>
#include <limits>

namespace masse::scene
{
Index nearestMass(const Particles& particles, const Vec3& point)
{
    Index best = 0;
    Real bestDistance = std::numeric_limits<Real>::infinity();
    for (std::size_t i = 0; i < particles.size(); ++i)
    {
        const Real d = (particles.position[i] - point).squaredNorm();
        if (d < bestDistance)
        {
            bestDistance = d;
            best = Index(i);
        }
    }
    return best;
}

ScriptRunner::ScriptRunner(std::vector<ScriptAction> actions, const Lattice& lattice,
                           bridge::BulletEnvironment& environment, EventSink sink, SceneAction sceneAction)
    : m_lattice(lattice), m_environment(environment), m_sink(std::move(sink)), m_sceneAction(std::move(sceneAction))
{
    for (ScriptAction& action : actions)
    {
        m_actions.push_back(std::make_unique<ScriptAction>(std::move(action)));
    }
    // Fire in time order; actions at the same time keep the file's order.
    std::stable_sort(m_actions.begin(), m_actions.end(),
                     [](const std::unique_ptr<ScriptAction>& a, const std::unique_ptr<ScriptAction>& b)
                     { return a->time < b->time; });
}

void ScriptRunner::add(ScriptAction action)
{
    // After every pending action at or before its time, as the stable sort of a file's actions would place it.
    auto at = m_actions.begin() + std::ptrdiff_t(m_next);
    while (at != m_actions.end() && (*at)->time <= action.time)
    {
        ++at;
    }
    m_actions.insert(at, std::make_unique<ScriptAction>(std::move(action)));
}

bool ScriptRunner::redirectGrab(MassSpringSystem& system, const std::string& label, const Vec3& target, Real time,
                                Real duration)
{
    ScriptAction* action = nullptr;
    UserSpring* spring = nullptr;
    for (Grab& grab : m_grabs)
    {
        if (grab.label == label)
        {
            action = grab.action;
            spring = system.userSprings.find(grab.spring);
            break;
        }
    }
    if (action == nullptr)
    {
        for (std::size_t k = m_next; k < m_actions.size() && m_actions[k]->time <= time + 1e-9; ++k)
        {
            if (m_actions[k]->kind == ScriptAction::Kind::Grab && m_actions[k]->label == label)
            {
                action = m_actions[k].get();
                break;
            }
        }
    }
    if (action == nullptr)
    {
        return false;
    }
    UserSpring from;
    aim(from, *action, time);
    action->path.clear();
    if (duration > 0)
    {
        action->path.emplace_back(time, from.target);
    }
    action->path.emplace_back(time + duration, target);
    if (spring != nullptr)
    {
        // The next frame's first substep pulls toward the new path, as it would toward a file's path at this time.
        aim(*spring, *action, time);
    }
    return true;
}

void ScriptRunner::aim(UserSpring& spring, const ScriptAction& action, Real time)
{
    const auto& path = action.path;
    if (time <= path.front().first)
    {
        spring.target = path.front().second;
        spring.targetVelocity.setZero();
        return;
    }
    for (std::size_t k = 0; k + 1 < path.size(); ++k)
    {
        const auto& [t0, p0] = path[k];
        const auto& [t1, p1] = path[k + 1];
        if (time < t1)
        {
            spring.targetVelocity = (p1 - p0) / (t1 - t0);
            spring.target = p0 + (time - t0) * spring.targetVelocity;
            return;
        }
    }
    spring.target = path.back().second;
    spring.targetVelocity.setZero();
}

void ScriptRunner::fire(MassSpringSystem& system, ScriptAction& action, Real time)
{
    switch (action.kind)
    {
    case ScriptAction::Kind::Grab:
    {
        const Index mass = action.grabNearest ? nearestMass(system.particles, action.point) : action.mass;
        UserSpring spring;
        spring.mass = mass;
        spring.stiffness = action.stiffness;
        spring.damping = action.damping;
        spring.maxForce = action.maxForce;
        aim(spring, action, time);
        const UserSpringId id = system.userSprings.add(spring);
        m_grabs.push_back({action.label, id, mass, &action});
        m_grabsFiredThisFrame.push_back(&action);
        system.markChanged();
        m_sink("grab", action.label.empty() ? "mass " + std::to_string(mass) : action.label, time);
        break;
    }
    case ScriptAction::Kind::Release:
        for (auto it = m_grabs.begin(); it != m_grabs.end(); ++it)
        {
            if (it->label == action.label)
            {
                system.userSprings.remove(it->spring);
                m_grabs.erase(it);
                system.markChanged();
                m_sink("release", action.label, time);
                break;
            }
        }
        break;
    case ScriptAction::Kind::Pin:
    case ScriptAction::Kind::Unpin:
    {
        const bool pin = action.kind == ScriptAction::Kind::Pin;
        const std::vector<Index> masses = resolvePins(action.masses, m_lattice);
        for (Index i : masses)
        {
            system.particles.setPinned(i, pin);
        }
        system.markChanged();
        m_sink(pin ? "pin" : "unpin", std::to_string(masses.size()) + " masses", time);
        break;
    }
    case ScriptAction::Kind::Gravity:
        system.forces.gravity = action.vector;
        system.markChanged();
        m_sink("gravity", "sheet", time);
        break;
    case ScriptAction::Kind::Move:
        m_environment.extendPath(m_environment.findObstacle(action.obstacle), action.obstaclePath);
        m_sink("move", action.obstacle, time);
        break;
    case ScriptAction::Kind::Steer:
        m_environment.steer(m_environment.findObstacle(action.obstacle), time, action.target, action.speed);
        m_sink("steer", action.obstacle, time);
        break;
    case ScriptAction::Kind::Heater:
    case ScriptAction::Kind::Ambient:
    case ScriptAction::Kind::ObstacleTemperature:
    case ScriptAction::Kind::Pressure:
        if (m_sceneAction)
        {
            m_sceneAction(action);
        }
        if (action.kind == ScriptAction::Kind::Heater)
        {
            m_sink(action.on ? "heater on" : "heater off", action.heater, time);
        }
        else if (action.kind == ScriptAction::Kind::Ambient)
        {
            m_sink("ambient", "air", time);
        }
        else if (action.kind == ScriptAction::Kind::ObstacleTemperature)
        {
            m_sink("obstacle temperature", action.obstacle, time);
        }
        else
        {
            m_sink("pressure", "sheet", time);
        }
        break;
    }
}

void ScriptRunner::beforeFrame(MassSpringSystem& system, StepContext& /*context*/, Real time)
{
    m_grabsFiredThisFrame.clear();
    // A small tolerance so an action at t = 0.3 fires at the frame that starts at 0.29999999999999999.
    while (m_next < m_actions.size() && m_actions[m_next]->time <= time + 1e-9)
    {
        fire(system, *m_actions[m_next], time);
        ++m_next;
    }
}

void ScriptRunner::afterSubstep(MassSpringSystem& system, StepContext& /*context*/, Real /*h*/, Real time)
{
    for (const Grab& grab : m_grabs)
    {
        if (UserSpring* spring = system.userSprings.find(grab.spring))
        {
            aim(*spring, *grab.action, time);
        }
    }
}

std::vector<const ScriptAction*> ScriptRunner::pending() const
{
    std::vector<const ScriptAction*> result;
    for (std::size_t k = m_next; k < m_actions.size(); ++k)
    {
        result.push_back(m_actions[k].get());
    }
    return result;
}

std::vector<std::string> ScriptRunner::grabLabels() const
{
    std::vector<std::string> labels;
    for (const Grab& grab : m_grabs)
    {
        labels.push_back(grab.label);
    }
    for (std::size_t k = m_next; k < m_actions.size(); ++k)
    {
        if (m_actions[k]->kind == ScriptAction::Kind::Grab)
        {
            labels.push_back(m_actions[k]->label);
        }
    }
    return labels;
}

std::string actionName(ScriptAction::Kind kind)
{
    switch (kind)
    {
    case ScriptAction::Kind::Grab:
        return "grab";
    case ScriptAction::Kind::Release:
        return "release";
    case ScriptAction::Kind::Pin:
        return "pin";
    case ScriptAction::Kind::Unpin:
        return "unpin";
    case ScriptAction::Kind::Gravity:
        return "gravity";
    case ScriptAction::Kind::Move:
        return "move";
    case ScriptAction::Kind::Heater:
        return "heater";
    case ScriptAction::Kind::Ambient:
        return "ambient";
    case ScriptAction::Kind::Pressure:
        return "pressure";
    case ScriptAction::Kind::Steer:
        return "steer";
    case ScriptAction::Kind::ObstacleTemperature:
        return "obstacle_temperature";
    }
    return "action";
}

std::vector<std::pair<Index, UserSpringId>> ScriptRunner::activeGrabs() const
{
    std::vector<std::pair<Index, UserSpringId>> result;
    for (const Grab& grab : m_grabs)
    {
        result.emplace_back(grab.mass, grab.spring);
    }
    return result;
}
} // namespace masse::scene
