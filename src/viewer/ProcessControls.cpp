#include "ProcessControls.h"

#include <algorithm>
#include <cmath>

namespace masse::viewer
{
namespace
{
void postAction(const CommandSink& post, scene::ScriptAction action)
{
    post([action = std::move(action)](ViewerSession& session) { session.act(action); });
}

scene::ScriptAction steerAction(const std::string& obstacle, const Vec3& target, Real speed)
{
    scene::ScriptAction action;
    action.kind = scene::ScriptAction::Kind::Steer;
    action.obstacle = obstacle;
    action.target = target;
    action.speed = speed;
    return action;
}
} // namespace

void ProcessControls::update(const SceneSnapshot& snapshot)
{
    if (snapshot.generation == m_generation)
    {
        return;
    }
    m_generation = snapshot.generation;
    m_target.reset();
    // The level the scene's own schedule reaches, the one most often wanted again.
    if (snapshot.spec && !snapshot.spec->forming.pressure.empty())
    {
        Real strongest = 0;
        for (const PressureKey& key : snapshot.spec->forming.pressure)
        {
            strongest = std::abs(key.pressure) > std::abs(strongest) ? key.pressure : strongest;
        }
        if (strongest != 0)
        {
            level = strongest;
        }
    }
}

void ProcessControls::switchPressure(const SceneSnapshot& snapshot, const CommandSink& post)
{
    setPressure(snapshot.process.pressure != 0 ? Real(0) : level, post);
}

void ProcessControls::setPressure(Real pascals, const CommandSink& post)
{
    scene::ScriptAction action;
    action.kind = scene::ScriptAction::Kind::Pressure;
    action.pressure = pascals;
    action.ramp = std::max(ramp, Real(0));
    postAction(post, std::move(action));
}

std::optional<std::size_t> ProcessControls::steeredObstacle(const SceneSnapshot& snapshot)
{
    for (std::size_t k = 0; k < snapshot.obstacles.size(); ++k)
    {
        if (snapshot.obstacles[k].kinematic && !snapshot.obstacles[k].partOfRoom)
        {
            return k;
        }
    }
    return std::nullopt;
}

void ProcessControls::nudge(const SceneSnapshot& snapshot, int direction, const CommandSink& post)
{
    const std::optional<std::size_t> k = steeredObstacle(snapshot);
    if (!k)
    {
        return;
    }
    const ObstacleShape& obstacle = snapshot.obstacles[*k];
    // Presses add up while the obstacle is still on its way to the last target; else from where it is.
    const bool moving = obstacle.velocity.squaredNorm() > 0;
    Vec3 target = moving && m_target ? *m_target : obstacle.position;
    target.y() += Real(direction) * step;
    m_target = target;
    postAction(post, steerAction(obstacle.name, target, speed));
}

void ProcessControls::beginDrag(const ObstacleShape& obstacle, Real grabbedY)
{
    m_dragged = obstacle.name;
    m_target = obstacle.position;
    m_dragOffset = obstacle.position.y() - grabbedY;
}

void ProcessControls::dragTo(Real y, const CommandSink& post)
{
    constexpr Real leastMove = 0.001; // m
    const Real height = y + m_dragOffset;
    if (m_dragged.empty() || !m_target || std::abs(height - m_target->y()) < leastMove)
    {
        return;
    }
    m_target->y() = height;
    postAction(post, steerAction(m_dragged, *m_target, speed));
}

void ProcessControls::stop(const SceneSnapshot& snapshot, const CommandSink& post)
{
    const std::optional<std::size_t> k = steeredObstacle(snapshot);
    if (!k)
    {
        return;
    }
    m_target.reset();
    const std::string name = snapshot.obstacles[*k].name;
    // Held where it is when the action fires (the simulation may have moved it since this snapshot).
    post(
        [name, speed = speed](ViewerSession& session)
        {
            const bridge::BulletEnvironment& environment = session.scene().environment();
            session.act(steerAction(name, environment.obstacle(environment.findObstacle(name)).pose.position, speed));
        });
}

void ProcessControls::setHeater(const std::string& heater, bool on, Real watts, const CommandSink& post)
{
    scene::ScriptAction action;
    action.kind = scene::ScriptAction::Kind::Heater;
    action.heater = heater;
    action.on = on;
    action.power = watts;
    postAction(post, std::move(action));
}

void ProcessControls::setObstacleTemperature(const std::string& obstacle, Real celsius, const CommandSink& post)
{
    scene::ScriptAction action;
    action.kind = scene::ScriptAction::Kind::ObstacleTemperature;
    action.obstacle = obstacle;
    action.temperature = celsius + 273.15;
    postAction(post, std::move(action));
}

void ProcessControls::setAmbient(Real celsius, const CommandSink& post)
{
    scene::ScriptAction action;
    action.kind = scene::ScriptAction::Kind::Ambient;
    action.temperature = celsius + 273.15;
    postAction(post, std::move(action));
}

std::string ProcessControls::savePath(const SceneSnapshot& snapshot) const
{
    if (!saveRunPath.empty())
    {
        return saveRunPath;
    }
    return (snapshot.spec ? snapshot.spec->name : std::string("scene")) + ".run.json";
}

void ProcessControls::saveRun(const SceneSnapshot& snapshot, const CommandSink& post)
{
    post([path = savePath(snapshot)](ViewerSession& session) { session.saveRun(path); });
}
} // namespace masse::viewer
