#include "scene/GuardBounds.h"

#include <algorithm>
#include <cmath>

namespace masse::scene
{
namespace
{
Real pathSpeed(const std::vector<bridge::PoseKey>& path, Real radius)
{
    Real fastest = 0;
    for (std::size_t k = 0; k + 1 < path.size(); ++k)
    {
        const Real dt = path[k + 1].time - path[k].time;
        const Real turn = path[k].orientation.angularDistance(path[k + 1].orientation);
        fastest = std::max(fastest, ((path[k + 1].position - path[k].position).norm() + turn * radius) / dt);
    }
    return fastest;
}
} // namespace

Real fastestObstacleSpeed(const SceneSpec& spec)
{
    Real fastest = 0;
    for (const ObstacleSpec& o : spec.obstacles)
    {
        std::vector<bridge::PoseKey> path = o.path;
        for (const ScriptAction& a : spec.script)
        {
            if (a.kind == ScriptAction::Kind::Move && a.obstacle == o.name)
            {
                path.insert(path.end(), a.obstaclePath.begin(), a.obstaclePath.end());
            }
        }
        fastest = std::max(fastest, pathSpeed(path, o.shape.reach()));
    }
    for (const ScriptAction& a : spec.script)
    {
        if (a.kind == ScriptAction::Kind::Steer)
        {
            fastest = std::max(fastest, a.speed);
        }
    }
    return fastest;
}

Real fastestScriptedSpeed(const SceneSpec& spec, Real lightestMass)
{
    // Gravity: a fall is bounded by the air's terminal speed g / c, by g times the run's length, and inside the room
    // by a fall of its whole height.
    Real gravity = spec.environment.gravity.stableNorm();
    for (const ScriptAction& a : spec.script)
    {
        if (a.kind == ScriptAction::Kind::Gravity)
        {
            gravity = std::max(gravity, a.vector.stableNorm());
        }
    }
    Real fall = gravity * spec.run.duration;
    if (spec.environment.airDampingRate > 0)
    {
        fall = std::min(fall, gravity / spec.environment.airDampingRate);
    }
    if (spec.environment.room.enabled)
    {
        const RoomSpec& room = spec.environment.room;
        // sqrt(2 g H), each factor apart so that a gravity near double's range does not overflow to an infinite bound.
        fall = std::min(fall, std::sqrt(gravity) * std::sqrt(2 * (room.maxCorner - room.minCorner).norm()));
    }
    // Grabs: their targets' speed, and the pull of a capped spring over the sheet's size and the path's reach.
    const LatticeSpec& sheet = spec.sheet.lattice;
    const Real size = (sheet.maxCorner - sheet.minCorner).norm();
    Real grabs = 0;
    for (const ScriptAction& a : spec.script)
    {
        if (a.kind != ScriptAction::Kind::Grab)
        {
            continue;
        }
        Real farthest = size;
        for (std::size_t k = 0; k < a.path.size(); ++k)
        {
            farthest = std::max(farthest, (a.path[k].second - sheet.minCorner).norm() + size);
            if (k + 1 < a.path.size())
            {
                grabs = std::max(grabs, (a.path[k + 1].second - a.path[k].second).norm() /
                                            (a.path[k + 1].first - a.path[k].first));
            }
        }
        grabs = std::max(grabs, std::sqrt(2 * a.maxForce * farthest / lightestMass));
    }
    // A forming pressure: the work p d it does on a sheet of areal mass rho h0 over the sheet's size d, and with air
    // drag no more than its terminal speed p / (rho h0 c). A wall the forming has thinned moves faster than either
    // (its areal mass is smaller), which the guard's margin covers down to a hundredth of h0. The pressure must be
    // among the causes: a wall thinned to 0.1 h0 is drawn onto the mould at tens of metres a second (the plug-assist
    // cup at 128x2x128), past the 24 m/s that the plug's speed alone would allow.
    Real pressure = 0;
    if (spec.forming.enabled && spec.material.enabled && spec.material.thickness > 0)
    {
        Real strongest = 0;
        for (const PressureKey& key : spec.forming.pressure)
        {
            strongest = std::max(strongest, std::abs(key.pressure));
        }
        for (const ScriptAction& a : spec.script)
        {
            if (a.kind == ScriptAction::Kind::Pressure)
            {
                strongest = std::max(strongest, std::abs(a.pressure));
            }
        }
        const Real arealMass = spec.material.material.density * spec.material.thickness;
        pressure = std::sqrt(2 * strongest * size / arealMass);
        if (spec.environment.airDampingRate > 0)
        {
            pressure = std::min(pressure, strongest / (arealMass * spec.environment.airDampingRate));
        }
    }
    return std::max({fall, grabs, pressure, fastestObstacleSpeed(spec)});
}

GuardSettings guardSettings(const SceneSpec& spec, Real lightestMass)
{
    GuardSettings settings;
    // A floor of 0.1 m/s for scenes where nothing drives the sheet (no gravity, no script).
    settings.speedLimit = guardSpeedMargin * std::max(fastestScriptedSpeed(spec, lightestMass), Real(0.1));
    settings.obstacleSpeed = fastestObstacleSpeed(spec);
    // A material sheet's springs are rewritten by its Burgers model every substep, and a glassy one's are stiff
    // (meganewtons per metre): the contact putting its bottom layer back by a millimetre stores a hundred joules in
    // them for a sheet whose weight times size is a tenth of a joule (measured on a 6x2x6 PET sheet), which the
    // implicit step damps away. Such sheets' account weighs the energy of motion only (EnergyAccount::Motion).
    settings.account = spec.material.enabled ? EnergyAccount::Motion : EnergyAccount::Mechanical;
    return settings;
}
} // namespace masse::scene
