#pragma once
/// The forming bench's controls: what the panel's process section and its keys ask of a forming scene (the vacuum or
/// pressure, the plug, the heaters, the mould's temperature, saving the run). Each change becomes a script action
/// (scene/SceneSpec.h: pressure, steer, heater, obstacle_temperature, ambient) posted to the simulation thread, which
/// adds it at the scene's time: it takes effect at the next frame, and "save run" writes it for `masse run` to replay.
/// No GL and no ImGui: the tests drive it as the panel does.

#include "SceneSnapshot.h"
#include "SimulationThread.h"

#include <functional>
#include <optional>
#include <string>

namespace masse::viewer
{
using CommandSink = std::function<void(SessionCommand)>;

class ProcessControls
{
public:
    /// Once a frame: a new scene (generation) starts from its own settings (its pressure level, no steer target).
    void update(const SceneSnapshot& snapshot);

    /// The vacuum or pressure on (at `level`, over `ramp`) when it is off, off when it is on.
    void switchPressure(const SceneSnapshot& snapshot, const CommandSink& post);
    /// The pressure to `pascals` over `ramp`.
    void setPressure(Real pascals, const CommandSink& post);
    /// The steered obstacle (the first kinematic one) down (-1) or up (+1) by `step`, at `speed`; repeated presses
    /// add up while it moves.
    void nudge(const SceneSnapshot& snapshot, int direction, const CommandSink& post);
    /// Alt + left drag on the view: the steered obstacle follows the cursor up and down (dragTo), from where it is
    /// with the cursor's point on the drag plane at height `grabbedY` (m).
    void beginDrag(const ObstacleShape& obstacle, Real grabbedY);
    /// The cursor's point now at height `y`: the obstacle to its height then plus the cursor's rise since, at `speed`;
    /// a steer each time that target has moved a millimetre or more, so a drag records a handful of actions, not
    /// one per mouse event.
    void dragTo(Real y, const CommandSink& post);
    /// The steered obstacle held where it is.
    void stop(const SceneSnapshot& snapshot, const CommandSink& post);
    void setHeater(const std::string& heater, bool on, Real watts, const CommandSink& post);
    void setObstacleTemperature(const std::string& obstacle, Real celsius, const CommandSink& post);
    void setAmbient(Real celsius, const CommandSink& post);
    void saveRun(const SceneSnapshot& snapshot, const CommandSink& post);

    /// The obstacle the keys steer: the first kinematic one not of the room; nullopt when there is none.
    static std::optional<std::size_t> steeredObstacle(const SceneSnapshot& snapshot);
    /// The file "save run" writes for this snapshot's scene.
    std::string savePath(const SceneSnapshot& snapshot) const;

    Real level = 80000;      ///< Pa, what switchPressure turns on
    Real ramp = 0.2;         ///< s, over which the pressure changes
    Real speed = 0.05;       ///< m/s, of the steered obstacle
    Real step = 0.01;        ///< m, of one nudge
    std::string saveRunPath; ///< where "save run" writes ("": "<scene name>.run.json" in the current folder)

private:
    std::uint64_t m_generation = ~std::uint64_t(0);
    std::optional<Vec3> m_target; ///< where the last nudge or drag sent the steered obstacle
    std::string m_dragged;        ///< the obstacle a drag moves
    Real m_dragOffset = 0;        ///< m, its height at the drag's start less the cursor's
};
} // namespace masse::viewer
