#include "scene/SavedRun.h"

#include "scene/SceneFile.h"
#include "scene/ScriptRunner.h"

#include "core/material/Material.h"

#include <cmath>
#include <filesystem>

namespace masse::scene
{
namespace
{
/// C that the reader, adding 273.15, turns back into `kelvin` to the last bit (kelvin - 273.15 may be an ulp off).
Real celsiusReadBackAs(Real kelvin)
{
    Real celsius = kelvinToCelsius(kelvin);
    for (int k = 0; k < 4 && celsiusToKelvin(celsius) != kelvin; ++k)
    {
        celsius = std::nextafter(celsius, celsiusToKelvin(celsius) < kelvin ? HUGE_VAL : -HUGE_VAL);
    }
    return celsius;
}

nlohmann::json pointJson(const Vec3& p)
{
    return nlohmann::json::array({p.x(), p.y(), p.z()});
}

nlohmann::json pinsJson(const PinSpec& spec)
{
    nlohmann::json masses = nlohmann::json::object();
    if (!spec.masses.empty())
    {
        masses["masses"] = spec.masses;
    }
    if (!spec.corners.empty())
    {
        masses["corners"] = spec.corners;
    }
    if (!spec.edges.empty())
    {
        masses["edges"] = spec.edges;
    }
    return masses;
}

/// Degrees about x, then y, then z (fixed axes), as rotationFromDegrees reads them: R = Rz Ry Rx.
nlohmann::json degreesJson(const Eigen::Quaternion<Real>& orientation)
{
    const Vec3 zyx = orientation.toRotationMatrix().eulerAngles(2, 1, 0) * (Real(180) / Real(M_PI));
    return nlohmann::json::array({zyx.z(), zyx.y(), zyx.x()});
}

/// A file's "sheet.size" from the --size flag, and the other flags as their keys.
void writeFlagsIntoDocument(const SceneFlags& flags, nlohmann::json& document)
{
    if (!flags.integrator.empty())
    {
        document["integrator"]["type"] = flags.integrator;
    }
    if (!flags.dt.empty())
    {
        document["integrator"]["dt"] = nlohmann::json::parse(flags.dt);
    }
    if (!flags.size.empty())
    {
        document["sheet"]["size"] = flags.size;
    }
}
} // namespace

nlohmann::json actionDocument(const ScriptAction& a)
{
    nlohmann::json item = {{"time", a.time}, {"action", actionName(a.kind)}};
    if (!a.label.empty() && a.kind != ScriptAction::Kind::Release)
    {
        item["label"] = a.label;
    }
    switch (a.kind)
    {
    case ScriptAction::Kind::Grab:
    {
        if (a.grabNearest)
        {
            item["near"] = pointJson(a.point);
        }
        else
        {
            item["mass"] = a.mass;
        }
        nlohmann::json path = nlohmann::json::array();
        for (const auto& [time, target] : a.path)
        {
            path.push_back({{"time", time}, {"position", pointJson(target)}});
        }
        item["path"] = path;
        item["stiffness"] = a.stiffness;
        item["damping"] = a.damping;
        item["max_force"] = a.maxForce;
        break;
    }
    case ScriptAction::Kind::Release:
        item["grab"] = a.label;
        break;
    case ScriptAction::Kind::Pin:
    case ScriptAction::Kind::Unpin:
        item["masses"] = pinsJson(a.masses);
        break;
    case ScriptAction::Kind::Gravity:
        item["value"] = pointJson(a.vector);
        break;
    case ScriptAction::Kind::Move:
    {
        item["obstacle"] = a.obstacle;
        nlohmann::json path = nlohmann::json::array();
        for (const bridge::PoseKey& key : a.obstaclePath)
        {
            nlohmann::json k = {{"time", key.time}, {"position", pointJson(key.position)}};
            if (!key.orientation.isApprox(Eigen::Quaternion<Real>::Identity(), 0))
            {
                k["rotation_deg"] = degreesJson(key.orientation);
            }
            path.push_back(k);
        }
        item["path"] = path;
        break;
    }
    case ScriptAction::Kind::Steer:
        item["obstacle"] = a.obstacle;
        item["to"] = pointJson(a.target);
        item["speed"] = a.speed;
        break;
    case ScriptAction::Kind::Heater:
        item["heater"] = a.heater;
        item["on"] = a.on;
        if (a.power >= 0)
        {
            item["power"] = a.power;
        }
        break;
    case ScriptAction::Kind::Ambient:
        item["temperature_c"] = celsiusReadBackAs(a.temperature);
        break;
    case ScriptAction::Kind::ObstacleTemperature:
        item["obstacle"] = a.obstacle;
        item["temperature_c"] = celsiusReadBackAs(a.temperature);
        break;
    case ScriptAction::Kind::Pressure:
        item["pressure"] = a.pressure;
        if (a.ramp > 0)
        {
            item["ramp"] = a.ramp;
        }
        break;
    }
    return item;
}

nlohmann::json savedRunDocument(const RunSource& source, const std::vector<ScriptAction>& added, Real duration)
{
    nlohmann::json document = readSceneDocument(source.path);
    // The saved file may go anywhere: its material and meshes are named by where they are.
    makePathsAbsolute(document, std::filesystem::path(source.path).parent_path());
    applyKeyOverrides(document, parseSettings(source.flags.settings));
    writeFlagsIntoDocument(source.flags, document);
    document.erase("expect"); // a regression's expected results are those of the scene, not of this run
    nlohmann::json& script = document["script"];
    if (!script.is_array())
    {
        script = nlohmann::json::array();
    }
    for (const ScriptAction& action : added)
    {
        script.push_back(actionDocument(action));
    }
    document["run"]["duration"] = duration;
    document["run"]["stop_at_rest"] = false;
    return document;
}
} // namespace masse::scene
