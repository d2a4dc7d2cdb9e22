#include "scene/SceneFile.h"

#include "scene/MaterialFile.h"
#include "scene/MemoryBudget.h"
#include "scene/PlausibleRanges.h"
#include "scene/json/FieldKeys.h"
#include "scene/json/JsonObject.h"
#include "scene/reports/ReportRegistry.h"
#include "scene/shapes/ShapeRegistry.h"

#include "core/Format.h"
#include "core/InputError.h"
#include "core/NearestName.h"
#include "core/forces/Damping.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <optional>
#include <sstream>
#include <utility>

namespace masse::scene
{
namespace
{
/// A spring stiffness in (0, limits::maxStiffness] N/m.
Real stiffnessValue(const JsonObject& o, const std::string& key, Real fallback)
{
    const Real value = o.positive(key, fallback);
    if (value > limits::maxStiffness)
    {
        o.fail(key, "must be in (0, " + formatNumber(limits::maxStiffness) + "] N/m (got " + formatNumber(value) + ")");
    }
    return value;
}

PinSpec readPins(const JsonObject& o)
{
    PinSpec pins;
    for (Real index : o.numbers("masses"))
    {
        // Checked before the cast: a double beyond Index's range does not convert (undefined behaviour).
        constexpr Real largest = Real(std::numeric_limits<Index>::max() - 1);
        if (index < 0 || index != std::floor(index) || index > largest)
        {
            o.fail("masses", "expected mass indices, whole numbers in [0, " + formatNumber("%.15g", largest) +
                                 "] (got " + formatNumber("%.15g", index) + ")");
        }
        pins.masses.push_back(Index(index));
    }
    for (Real corner : o.numbers("corners"))
    {
        if (corner != 0 && corner != 1 && corner != 2 && corner != 3)
        {
            o.fail("corners", "corners are 0, 1, 2, 3 (got " + formatNumber(corner) + ")");
        }
        pins.corners.push_back(int(corner));
    }
    if (const nlohmann::json* edges = o.raw("edges"))
    {
        if (!edges->is_array())
        {
            o.fail("edges", "expected a list of x_min, x_max, z_min, z_max");
        }
        for (const nlohmann::json& edge : *edges)
        {
            const std::string name = edge.is_string() ? edge.get<std::string>() : "";
            if (name != "x_min" && name != "x_max" && name != "z_min" && name != "z_max")
            {
                o.fail("edges", "unknown edge " + edge.dump() + " (expected x_min, x_max, z_min, z_max)");
            }
            pins.edges.push_back(name);
        }
    }
    o.finish();
    return pins;
}

SheetSpec readSheet(const JsonObject& o)
{
    SheetSpec sheet;
    LatticeSpec& lattice = sheet.lattice;
    lattice.structure = parseStructure(o.choice("structure", "trimm", namesOf(structureTable)));
    checkUnder("sheet", latticeKeys, [&] { parseSize(o.string("size", "8x2x8"), lattice); });
    lattice.minCorner = plausible::point(o, "min", lattice.minCorner);
    lattice.maxCorner = plausible::point(o, "max", lattice.maxCorner);
    checkUnder("sheet", latticeKeys, [&] { validate(lattice); });
    plausible::checkSheetHeight(o, "max", lattice.minCorner, lattice.maxCorner);

    SheetParams& params = sheet.params;
    params.massPerMass = o.number("mass", params.massPerMass, limits::minMass, limits::maxMass);
    if (auto stiffness = o.object("stiffness"))
    {
        params.springClasses[0].stiffness = stiffnessValue(*stiffness, "planar", params.springClasses[0].stiffness);
        params.springClasses[1].stiffness =
            stiffnessValue(*stiffness, "inter_layer", params.springClasses[1].stiffness);
        stiffness->finish();
    }
    if (auto damping = o.object("damping"))
    {
        params.springClasses[0].dampingRatio = damping->number("planar", params.springClasses[0].dampingRatio, 0, 10);
        params.springClasses[1].dampingRatio =
            damping->number("inter_layer", params.springClasses[1].dampingRatio, 0, 10);
        damping->finish();
    }
    sheet.repulsion = o.number("repulsion", 0.0, 0.0, limits::maxRepulsion);
    sheet.rotationDegrees = o.vec3("rotation_deg", Vec3::Zero());
    if (auto pinned = o.object("pinned"))
    {
        sheet.pinned = readPins(*pinned);
    }
    o.finish();
    return sheet;
}

EnvironmentSpec readEnvironment(const JsonObject& o)
{
    EnvironmentSpec environment;
    environment.gravity = plausible::gravity(o, "gravity", environment.gravity);
    if (o.has("air_retention") && o.has("air_damping_rate"))
    {
        o.fail("air_damping_rate", "give either air_retention or air_damping_rate, not both");
    }
    environment.airDampingRate = airDampingRate(paperAirRetention, paperTimeStep);
    if (o.has("air_retention"))
    {
        const Real retention = o.number("air_retention", paperAirRetention, 1e-6, 1.0);
        environment.airDampingRate = airDampingRate(retention, paperTimeStep);
    }
    environment.airDampingRate = o.number("air_damping_rate", environment.airDampingRate, 0.0);
    if (auto room = o.object("room"))
    {
        RoomSpec& r = environment.room;
        r.enabled = room->boolean("enabled", r.enabled);
        r.minCorner = plausible::point(*room, "min", r.minCorner);
        r.maxCorner = plausible::point(*room, "max", r.maxCorner);
        r.wallThickness = room->positive("wall_thickness", r.wallThickness);
        plausible::checkLength(*room, "wall_thickness", r.wallThickness);
        room->finish();
        validate(r);
    }
    o.finish();
    return environment;
}

std::vector<bridge::PoseKey> readPath(const JsonObject& owner, const std::string& key)
{
    std::vector<bridge::PoseKey> path;
    for (const JsonObject& k : owner.objects(key))
    {
        bridge::PoseKey pathKey;
        pathKey.time = k.number("time", 0.0, 0.0);
        pathKey.position = plausible::point(k, "position");
        pathKey.orientation = rotationFromDegrees(k.vec3("rotation_deg", Vec3::Zero()));
        k.finish();
        if (!path.empty() && !(pathKey.time > path.back().time))
        {
            owner.fail(key, "keys must come in increasing time");
        }
        path.push_back(pathKey);
    }
    return path;
}

constexpr Real kelvinAtZeroCelsius = 273.15;

ObstacleSpec readObstacle(const JsonObject& o, const std::string& baseDirectory, Real& temperature,
                          ObstacleContact& contact)
{
    if (auto own = o.object("contact"))
    {
        // An obstacle's own response (a plug that slides while the mould grips): response and friction only.
        contact.own = true;
        contact.response = parseContactResponse(own->choice("response", "friction", contactResponseNames()));
        contact.friction = own->number("friction", 0.3, 0.0);
        own->finish();
    }
    ObstacleSpec spec;
    temperature = std::numeric_limits<Real>::quiet_NaN();
    if (o.has("temperature_c"))
    {
        temperature = o.number("temperature_c", 20.0, -kelvinAtZeroCelsius + 1e-6) + kelvinAtZeroCelsius;
    }
    spec.name = o.string("name");
    const std::vector<std::string> shapeNames = scene::shapeNames();
    const ShapeEntry& shape = shapeNamed(o.choice("type", shapeNames.front(), shapeNames));
    spec.position = plausible::point(o, "position", Vec3::Zero());
    spec.orientation = rotationFromDegrees(o.vec3("rotation_deg", Vec3::Zero()));
    spec.shape = {&shape, shape.read(o, baseDirectory)};
    spec.path = readPath(o, "path");
    o.finish();
    return spec;
}

ContactSettings readContact(const JsonObject& o, bool& selfCollision, Real& selfFriction, bool& edgeCollision,
                            std::optional<bool>& keepLayers)
{
    ContactSettings contact;
    contact.response = parseContactResponse(o.choice("response", "friction", contactResponseNames()));
    contact.radius = o.positive("radius", contact.radius);
    if (contact.radius > limits::maxContactRadius)
    {
        o.fail("radius", "must be in (0, " + formatNumber(limits::maxContactRadius) + "] m (got " +
                             formatNumber(contact.radius) + ")");
    }
    contact.friction = o.number("friction", contact.friction, 0.0);
    contact.stickReleaseForce = o.number("release_force", contact.stickReleaseForce, 0.0);
    contact.slipRegularization = o.positive("slip_regularization", contact.slipRegularization);
    selfCollision = o.boolean("self_collision", selfCollision);
    selfFriction = o.number("self_friction", selfFriction, 0.0);
    edgeCollision = o.boolean("edge_collision", edgeCollision);
    if (o.has("keep_layers"))
    {
        keepLayers = o.boolean("keep_layers", false);
    }
    o.finish();
    return contact;
}

TimeSpec readTime(const JsonObject& o)
{
    TimeSpec time;
    time.integrator = parseIntegrator(o.choice("type", "symplectic", namesOf(integratorTable)));
    time.dt = o.number("dt", time.dt, limits::minTimeStep, limits::maxTimeStep);
    time.stabilitySafety = o.number("safety", time.stabilitySafety, 1e-3, 1.0);
    if (o.has("max_motion"))
    {
        time.maxMotion = o.number("max_motion", 0, 0, 1000);
    }
    time.implicit.tolerance = o.number("tolerance", time.implicit.tolerance, 1e-14, 0.1);
    time.implicit.maxIterations = o.integer("max_iterations", time.implicit.maxIterations, 1, 1000000);
    time.implicit.preconditioner =
        parsePreconditioner(o.choice("preconditioner", std::string(preconditionerName(time.implicit.preconditioner)),
                                     {std::string(preconditionerName(PreconditionerKind::Multigrid)),
                                      std::string(preconditionerName(PreconditionerKind::Cholesky)),
                                      std::string(preconditionerName(PreconditionerKind::Jacobi))}));
    o.finish();
    return time;
}

RunSpec readRun(const JsonObject& o)
{
    RunSpec run;
    run.duration = o.positive("duration", run.duration);
    if (run.duration > limits::maxDuration)
    {
        o.fail("duration",
               "must be in (0, " + formatNumber(limits::maxDuration) + "] s (got " + formatNumber(run.duration) + ")");
    }
    if (const nlohmann::json* rest = o.raw("stop_at_rest"))
    {
        if (rest->is_boolean())
        {
            run.stopAtRest = rest->get<bool>();
        }
        else
        {
            const JsonObject r(*rest, o.pathOf("stop_at_rest"));
            run.stopAtRest = r.boolean("enabled", true);
            run.restKineticEnergy = r.positive("kinetic_energy", run.restKineticEnergy);
            run.restHold = r.number("hold", run.restHold, 0.0);
            if (const nlohmann::json* after = r.raw("after_contact_with"))
            {
                if (!after->is_array())
                {
                    r.fail("after_contact_with", "expected a list of obstacle names");
                }
                for (const nlohmann::json& name : *after)
                {
                    if (!name.is_string())
                    {
                        r.fail("after_contact_with", "expected obstacle names (got " + name.dump() + ")");
                    }
                    run.restAfterContactWith.push_back(name.get<std::string>());
                }
            }
            r.finish();
        }
    }
    o.finish();
    return run;
}

ScriptAction readAction(const JsonObject& o)
{
    ScriptAction action;
    action.time = o.number("time", 0.0, 0.0);
    const std::string kind = o.choice("action", "grab",
                                      {"grab", "release", "pin", "unpin", "gravity", "move", "steer", "heater",
                                       "ambient", "pressure", "obstacle_temperature"});
    action.label = o.string("label", "");
    if (kind == "grab")
    {
        action.kind = ScriptAction::Kind::Grab;
        if (o.has("mass") == o.has("near"))
        {
            o.fail("mass", "a grab names either a mass index (mass) or a point to grab the nearest mass to (near)");
        }
        action.mass = Index(o.integer("mass", 0, 0, std::numeric_limits<int>::max()));
        action.grabNearest = o.has("near");
        action.point = plausible::point(o, "near", Vec3::Zero());
        for (const JsonObject& k : o.objects("path"))
        {
            const Real t = k.number("time", action.time, action.time);
            if (!action.path.empty() && !(t > action.path.back().first))
            {
                o.fail("path", "keys must come in increasing time");
            }
            action.path.emplace_back(t, plausible::point(k, "position"));
            k.finish();
        }
        if (action.path.empty())
        {
            o.fail("path", "a grab needs a path of at least one {\"time\", \"position\"} key");
        }
        action.stiffness = stiffnessValue(o, "stiffness", action.stiffness);
        action.damping = o.number("damping", action.damping, 0.0);
        action.maxForce = o.positive("max_force", action.maxForce);
        if (action.maxForce > plausible::maxGrabForce)
        {
            o.fail("max_force", "must be in (0, " + formatNumber(plausible::maxGrabForce) + "] N (got " +
                                    formatNumber(action.maxForce) + ")");
        }
    }
    else if (kind == "release")
    {
        action.kind = ScriptAction::Kind::Release;
        action.label = o.string("grab");
    }
    else if (kind == "pin" || kind == "unpin")
    {
        action.kind = kind == "pin" ? ScriptAction::Kind::Pin : ScriptAction::Kind::Unpin;
        action.masses = readPins(o.object("masses").value_or(JsonObject(nlohmann::json::object(), o.pathOf("masses"))));
    }
    else if (kind == "gravity")
    {
        action.kind = ScriptAction::Kind::Gravity;
        action.vector = plausible::gravity(o, "value");
    }
    else if (kind == "heater")
    {
        action.kind = ScriptAction::Kind::Heater;
        action.heater = o.string("heater");
        action.on = o.boolean("on", true);
        if (o.has("power"))
        {
            action.power = o.number("power", 0.0, 0.0); // checked against the panel's size with the scene
        }
    }
    else if (kind == "pressure")
    {
        action.kind = ScriptAction::Kind::Pressure;
        action.pressure = o.number("pressure");
        action.ramp = o.number("ramp", 0.0, 0.0, limits::maxDuration);
    }
    else if (kind == "steer")
    {
        action.kind = ScriptAction::Kind::Steer;
        action.obstacle = o.string("obstacle");
        action.target = plausible::point(o, "to");
        action.speed = o.number("speed");
        if (!(action.speed > 0) || action.speed > plausible::maxSteerSpeed)
        {
            o.fail("speed", "must be in (0, " + formatNumber(plausible::maxSteerSpeed) + "] m/s (got " +
                                formatNumber(action.speed) + ")");
        }
    }
    else if (kind == "obstacle_temperature")
    {
        action.kind = ScriptAction::Kind::ObstacleTemperature;
        action.obstacle = o.string("obstacle");
        action.temperature = o.number("temperature_c") + kelvinAtZeroCelsius;
        if (!(action.temperature > 0))
        {
            o.fail("temperature_c", "must be above absolute zero, -273.15 C");
        }
    }
    else if (kind == "ambient")
    {
        action.kind = ScriptAction::Kind::Ambient;
        action.temperature = o.number("temperature_c") + kelvinAtZeroCelsius;
        if (!(action.temperature > 0))
        {
            o.fail("temperature_c", "must be above absolute zero, -273.15 C");
        }
    }
    else
    {
        action.kind = ScriptAction::Kind::Move;
        action.obstacle = o.string("obstacle");
        action.obstaclePath = readPath(o, "path");
        if (action.obstaclePath.empty())
        {
            o.fail("path", "a move needs a path of at least one key");
        }
    }
    o.finish();
    return action;
}

OutputSpec readOutput(const JsonObject& o)
{
    OutputSpec output;
    output.framesEvery = o.integer("frames_every", 0, 0, 1000000);
    if (const nlohmann::json* formats = o.raw("formats"))
    {
        if (!formats->is_array())
        {
            o.fail("formats", "expected a list of vtp, obj");
        }
        for (const nlohmann::json& f : *formats)
        {
            if (!f.is_string() || (f.get<std::string>() != "vtp" && f.get<std::string>() != "obj"))
            {
                o.fail("formats", "unknown format " + f.dump() + " (expected vtp, obj)");
            }
            output.formats.push_back(f.get<std::string>());
        }
    }
    else if (output.framesEvery > 0)
    {
        output.formats = {"vtp"};
    }
    output.objSprings = o.boolean("obj_springs", false);
    o.finish();
    return output;
}

/// A number in a range whose ends may be open: "bullet.kLST: must be in (0, 1] (got 1.5)".
Real fraction(const JsonObject& o, const std::string& key, Real fallback, Real lo, bool loOpen, Real hi, bool hiOpen)
{
    if (!o.has(key))
    {
        return fallback;
    }
    const Real value = o.number(key);
    const bool aboveLo = loOpen ? value > lo : value >= lo;
    const bool belowHi = hiOpen ? value < hi : value <= hi;
    if (!(aboveLo && belowHi))
    {
        std::ostringstream message;
        message << "must be in " << (loOpen ? "(" : "[") << lo << ", " << hi << (hiOpen ? ")" : "]") << " (got "
                << value << ")";
        o.fail(key, message.str());
    }
    return value;
}

MaterialSpec readMaterialSection(const JsonObject& o, const std::string& baseDirectory)
{
    MaterialSpec spec;
    spec.enabled = true;
    if (o.has("file") == o.has("properties"))
    {
        o.fail("file",
               "give the material as a file (\"file\": \"../materials/abs.json\") or inline (\"properties\": {...})");
    }
    if (o.has("file"))
    {
        const std::filesystem::path file = o.string("file");
        spec.file = file.is_absolute() ? file.string() : (std::filesystem::path(baseDirectory) / file).string();
        spec.material = readMaterialFile(spec.file);
    }
    else
    {
        spec.material = parseMaterial(*o.object("properties"));
    }
    spec.thickness = plausible::thickness(o, "thickness", spec.thickness);
    spec.springs.model = parseSpringModel(o.choice("spring_model", "burgers", springModelNames()));
    spec.springs.dampingRatio = o.number("damping_ratio", spec.springs.dampingRatio, 0.0, 1.0);
    spec.springs.followThickness = o.boolean("follow_thickness", spec.springs.followThickness);
    spec.springs.strainHardening = o.number("strain_hardening", spec.springs.strainHardening, 0.0, maxStrainHardening);
    o.finish();
    return spec;
}

Real celsius(const JsonObject& o, const std::string& key, Real fallbackKelvin)
{
    const Real value = o.number(key, fallbackKelvin - kelvinAtZeroCelsius) + kelvinAtZeroCelsius;
    if (!(value > 0))
    {
        o.fail(key, "must be above absolute zero, -273.15 C");
    }
    return value;
}

HeatSpec readHeat(const JsonObject& o)
{
    HeatSpec heat;
    heat.enabled = true;
    ThermalSettings& t = heat.settings;
    t.initialTemperature = celsius(o, "initial_temperature_c", t.initialTemperature);
    t.airTemperature = celsius(o, "air_temperature_c", t.airTemperature);
    t.airHeatTransfer = o.number("air_heat_transfer", t.airHeatTransfer, 0.0);
    t.absorptivity = o.number("absorptivity", t.absorptivity, 0.0, 1.0);
    t.contactHeatTransfer = o.number("contact_heat_transfer", t.contactHeatTransfer, 0.0);
    t.solverTolerance = o.number("solver_tolerance", t.solverTolerance, 1e-14, 1e-3);
    t.maxIterations = o.integer("max_iterations", t.maxIterations, 1, 1000000);
    for (const JsonObject& h : o.objects("heaters"))
    {
        RadiantHeater heater;
        const std::string name = h.string("name");
        heater.centre = plausible::point(h, "centre", heater.centre);
        heater.normal = h.vec3("normal", heater.normal);
        heater.widthAxis = h.vec3("width_axis", heater.widthAxis);
        heater.width = h.number("width", heater.width);
        heater.length = h.number("length", heater.length);
        plausible::checkHeaterSide(h, "width", heater.width);
        plausible::checkHeaterSide(h, "length", heater.length);
        heater.power = h.number("power", heater.power);
        plausible::checkHeaterPower(h, "power", heater.power, heater.width, heater.length);
        const bool on = h.boolean("on", true);
        h.finish();
        heat.heaterNames.push_back(name);
        heat.heaterPower.push_back(heater.power);
        heat.heaterOn.push_back(on);
        if (!on)
        {
            heater.power = 0;
        }
        t.heaters.push_back(heater);
    }
    for (const JsonObject& z : o.objects("hot_air_zones"))
    {
        HotAirZone zone;
        heat.zoneNames.push_back(z.string("name", "zone " + std::to_string(heat.zoneNames.size())));
        zone.minCorner = plausible::point(z, "min", zone.minCorner);
        zone.maxCorner = plausible::point(z, "max", zone.maxCorner);
        zone.temperature = celsius(z, "temperature_c", zone.temperature);
        zone.heatTransfer = z.number("heat_transfer", zone.heatTransfer);
        z.finish();
        t.hotAirZones.push_back(zone);
    }
    o.finish();
    // Heaters with their full power are checked even if they start switched off.
    ThermalSettings check = t;
    for (std::size_t i = 0; i < check.heaters.size(); ++i)
    {
        check.heaters[i].power = heat.heaterPower[i];
    }
    checkUnder("heat", thermalKeys, [&] { validate(check); });
    return heat;
}

BulletSpec readBullet(const JsonObject& o)
{
    BulletSpec bullet;
    bridge::SoftBodyTwinSettings& s = bullet.settings;
    auto optional = [&](const std::string& key, Real lo, bool loOpen, Real hi, bool hiOpen) -> std::optional<Real>
    {
        if (!o.has(key))
        {
            return std::nullopt;
        }
        return fraction(o, key, 0, lo, loOpen, hi, hiOpen);
    };
    s.kLST = optional("kLST", 0, true, 1, false);
    s.kDP = optional("kDP", 0, false, 1, true);
    s.kDF = optional("kDF", 0, false, 1, false);
    s.kCHR = fraction(o, "kCHR", s.kCHR, 0, false, 1, false);
    s.kKHR = fraction(o, "kKHR", s.kKHR, 0, false, 1, false);
    s.margin = optional("margin", 0, true, 1, false);
    s.piterations = o.integer("piterations", s.piterations, 1, 1000);
    s.substeps = o.integer("substeps", s.substeps, 1, 10000);
    s.sdfCellSize = fraction(o, "sdf_cell_size", s.sdfCellSize, 0.001, false, 1, false);
    bullet.collisions = o.string("collisions", bullet.collisions);
    bullet.calibrate = o.boolean("calibrate", false);
    if (bullet.calibrate && s.kLST)
    {
        o.fail("calibrate", "give either kLST or calibrate: true, not both");
    }
    // The twin's node-versus-obstacle collision is Bullet's SDF_RS; the other modes are refused with the reason.
    if (bullet.collisions == "CL_RS")
    {
        o.fail("collisions", "CL_RS is not supported: cluster collision needs the sheet cut into clusters and reports "
                             "contact per cluster, not per node; use SDF_RS");
    }
    if (bullet.collisions.rfind("SDF_RD", 0) == 0)
    {
        o.fail("collisions", bullet.collisions +
                                 " is not supported: it belongs to btDeformableMultiBodyDynamicsWorld, not to the "
                                 "classic soft body the twin uses; use SDF_RS");
    }
    if (bullet.collisions != "SDF_RS")
    {
        o.fail("collisions", "must be SDF_RS (got '" + bullet.collisions + "')");
    }
    checkUnder(o.path(), bulletKeys, [&] { bridge::validate(s); }); // what the ranges above did not catch
    o.finish();
    return bullet;
}

/// Every temperature a heat scene gives, against the material's upper limit: a sheet started or driven past it is
/// outside the material's model (and 293 there is most often 20 C given in kelvin).
void checkTemperatures(const SceneSpec& scene, const JsonObject& top)
{
    if (!scene.heat.enabled)
    {
        return;
    }
    const Material& material = scene.material.material;
    const ThermalSettings& t = scene.heat.settings;
    plausible::checkTemperature(top, "heat.initial_temperature_c", t.initialTemperature, material);
    plausible::checkTemperature(top, "heat.air_temperature_c", t.airTemperature, material);
    for (std::size_t i = 0; i < t.hotAirZones.size(); ++i)
    {
        plausible::checkTemperature(top, "heat.hot_air_zones[" + std::to_string(i) + "].temperature_c",
                                    t.hotAirZones[i].temperature, material);
    }
    for (std::size_t i = 0; i < scene.obstacleTemperature.size(); ++i)
    {
        plausible::checkTemperature(top, "obstacles[" + std::to_string(i) + "].temperature_c",
                                    scene.obstacleTemperature[i], material); // NaN (the air's) passes
    }
    for (std::size_t i = 0; i < scene.script.size(); ++i)
    {
        const ScriptAction& a = scene.script[i];
        const std::string key = "script[" + std::to_string(i) + "]";
        if (a.kind == ScriptAction::Kind::Ambient || a.kind == ScriptAction::Kind::ObstacleTemperature)
        {
            plausible::checkTemperature(top, key + ".temperature_c", a.temperature, material);
        }
        const auto heater = std::find(scene.heat.heaterNames.begin(), scene.heat.heaterNames.end(), a.heater);
        if (a.kind == ScriptAction::Kind::Heater && a.power >= 0 && heater != scene.heat.heaterNames.end())
        {
            const RadiantHeater& panel = t.heaters[std::size_t(heater - scene.heat.heaterNames.begin())];
            plausible::checkHeaterPower(top, key + ".power", a.power, panel.width, panel.length);
        }
    }
}

/// Cross-checks of things that name other things: script targets, mass indices, contact obstacle lists.
void checkReferences(const SceneSpec& scene, const JsonObject& top)
{
    checkMassIndices(scene);

    std::vector<std::string> names;
    if (scene.environment.room.enabled)
    {
        for (const ObstacleSpec& wall : roomObstacles(scene.environment.room))
        {
            names.push_back(wall.name);
        }
    }
    for (const ObstacleSpec& o : scene.obstacles)
    {
        names.push_back(o.name);
    }
    auto exists = [&](const std::string& name) { return std::find(names.begin(), names.end(), name) != names.end(); };
    if (!scene.forming.mould.empty() && !exists(scene.forming.mould))
    {
        top.fail("forming.mould",
                 "no obstacle is named '" + scene.forming.mould + "'" + didYouMean(scene.forming.mould, names));
    }
    for (std::size_t i = 0; i < scene.run.restAfterContactWith.size(); ++i)
    {
        if (!exists(scene.run.restAfterContactWith[i]))
        {
            top.fail("run.stop_at_rest.after_contact_with", "no obstacle is named '" +
                                                                scene.run.restAfterContactWith[i] + "'" +
                                                                didYouMean(scene.run.restAfterContactWith[i], names));
        }
    }
    ScriptTargets targets;
    targets.masses = massCountOf(scene.sheet.lattice);
    targets.obstacles = names;
    for (const ObstacleSpec& o : scene.obstacles)
    {
        if (!o.isKinematic())
        {
            targets.staticObstacles.push_back(o.name);
        }
    }
    targets.heaters = scene.heat.heaterNames;
    targets.heat = scene.heat.enabled;
    targets.forming = scene.forming.enabled;
    for (std::size_t i = 0; i < scene.script.size(); ++i)
    {
        const ScriptAction& a = scene.script[i];
        const std::string key = "script[" + std::to_string(i) + "]";
        try
        {
            checkScriptAction(a, targets);
        }
        catch (const InputError& e)
        {
            top.fail(key + "." + e.field(), e.problem());
        }
        if (a.kind == ScriptAction::Kind::Grab && !a.label.empty())
        {
            targets.grabs.push_back(a.label);
        }
    }
}
} // namespace

void checkMassIndices(const SceneSpec& scene)
{
    const LatticeSpec& lattice = scene.sheet.lattice;
    const std::size_t masses = massCountOf(lattice); // counted, not built: a huge sheet is refused later
    auto check = [&](std::size_t mass, const std::string& key)
    {
        if (mass >= masses)
        {
            throw InputError(key, std::to_string(mass) + " is beyond the sheet's " + std::to_string(masses) +
                                      " masses, 0 to " + std::to_string(masses - 1) + " (" + scene.sheet.sizeGiven +
                                      " " + std::to_string(lattice.countX) + "x" + std::to_string(lattice.layers) +
                                      "x" + std::to_string(lattice.countZ) + ")");
        }
    };
    for (const Index mass : scene.sheet.pinned.masses)
    {
        check(mass, "sheet.pinned.masses");
    }
    for (const ReportEntry* report : reports())
    {
        if (report->massesNamed)
        {
            for (const NamedMass& named : report->massesNamed(scene))
            {
                check(named.mass, named.key);
            }
        }
    }
    for (std::size_t i = 0; i < scene.script.size(); ++i)
    {
        const ScriptAction& a = scene.script[i];
        const std::string key = "script[" + std::to_string(i) + "]";
        if (a.kind == ScriptAction::Kind::Grab && !a.grabNearest)
        {
            check(a.mass, key + ".mass");
        }
        if (a.kind == ScriptAction::Kind::Pin || a.kind == ScriptAction::Kind::Unpin)
        {
            for (const Index mass : a.masses.masses)
            {
                check(mass, key + ".masses.masses");
            }
        }
    }
}

ScriptAction readScriptAction(const nlohmann::json& action, const std::string& where)
{
    return readAction(JsonObject(action, where));
}

void checkScriptAction(const ScriptAction& a, const ScriptTargets& targets)
{
    const auto has = [](const std::vector<std::string>& names, const std::string& name)
    { return std::find(names.begin(), names.end(), name) != names.end(); };
    switch (a.kind)
    {
    case ScriptAction::Kind::Grab:
        if (!a.grabNearest && a.mass >= targets.masses)
        {
            throw InputError("mass", "mass " + std::to_string(a.mass) + " does not exist (the sheet has " +
                                         std::to_string(targets.masses) + " masses)");
        }
        break;
    case ScriptAction::Kind::Release:
        if (!has(targets.grabs, a.label))
        {
            throw InputError("grab", "no earlier grab is labelled '" + a.label + "'");
        }
        break;
    case ScriptAction::Kind::Pin:
    case ScriptAction::Kind::Unpin:
        for (Index m : a.masses.masses)
        {
            if (m >= targets.masses)
            {
                throw InputError("masses.masses", "mass " + std::to_string(m) + " does not exist (the sheet has " +
                                                      std::to_string(targets.masses) + " masses, 0 to " +
                                                      std::to_string(targets.masses - 1) + ")");
            }
        }
        break;
    case ScriptAction::Kind::Move:
    case ScriptAction::Kind::Steer:
        if (!has(targets.obstacles, a.obstacle))
        {
            throw InputError("obstacle",
                             "no obstacle is named '" + a.obstacle + "'" + didYouMean(a.obstacle, targets.obstacles));
        }
        if (has(targets.staticObstacles, a.obstacle))
        {
            throw InputError("obstacle", "'" + a.obstacle +
                                             "' is static: give it a \"path\" (at least one key) to make it kinematic");
        }
        break;
    case ScriptAction::Kind::Gravity:
        break;
    case ScriptAction::Kind::Heater:
        if (!has(targets.heaters, a.heater))
        {
            throw InputError("heater", "no heater is named '" + a.heater + "'" + didYouMean(a.heater, targets.heaters));
        }
        break;
    case ScriptAction::Kind::Ambient:
        if (!targets.heat)
        {
            throw InputError("action", "an ambient temperature needs a \"heat\" section");
        }
        break;
    case ScriptAction::Kind::ObstacleTemperature:
        if (!targets.heat)
        {
            throw InputError("action", "an obstacle's temperature needs a \"heat\" section");
        }
        if (!has(targets.obstacles, a.obstacle))
        {
            throw InputError("obstacle",
                             "no obstacle is named '" + a.obstacle + "'" + didYouMean(a.obstacle, targets.obstacles));
        }
        break;
    case ScriptAction::Kind::Pressure:
        if (!targets.forming)
        {
            throw InputError("action", "a forming pressure needs a \"forming\" section");
        }
        break;
    }
}

void checkRunLength(Real dt, Real duration, const std::string& stepKey, const std::string& durationKey)
{
    if (duration / dt > limits::maxSteps)
    {
        throw InputError(durationKey + " / " + stepKey + ": " + formatNumber(duration) + " s in steps of " +
                         formatNumber(dt) + " s is " + formatNumber(duration / dt) + " steps, over the limit of " +
                         formatNumber(limits::maxSteps));
    }
}

SceneSpec parseScene(const nlohmann::json& document, const std::string& baseDirectory, const std::string& origin)
{
    if (document.is_object() && document.contains("extends"))
    {
        throw InputError(origin + ": extends: only scene files may extend another (use loadScene)");
    }
    try
    {
        const JsonObject top(document, "");
        SceneSpec scene;
        scene.name = top.string("name", std::filesystem::path(origin).stem().string());
        scene.description = top.string("description", "");
        scene.path = origin;
        const nlohmann::json empty = nlohmann::json::object();
        scene.sheet = readSheet(top.object("sheet").value_or(JsonObject(empty, "sheet")));
        scene.environment = readEnvironment(top.object("environment").value_or(JsonObject(empty, "environment")));
        for (const JsonObject& o : top.objects("obstacles"))
        {
            Real temperature = 0;
            ObstacleContact contact;
            scene.obstacles.push_back(readObstacle(o, baseDirectory, temperature, contact));
            scene.obstacleTemperature.push_back(temperature);
            scene.obstacleContact.push_back(contact);
        }
        if (auto material = top.object("material"))
        {
            scene.material = readMaterialSection(*material, baseDirectory);
            for (const char* key : {"mass", "stiffness"})
            {
                if (top.object("sheet") && top.object("sheet")->has(key))
                {
                    top.fail(std::string("sheet.") + key,
                             "not used with a material: its density, modulus and thickness set the masses and springs");
                }
            }
        }
        if (auto heat = top.object("heat"))
        {
            if (!scene.material.enabled)
            {
                top.fail("heat", "needs a \"material\" to know how the sheet heats and softens");
            }
            scene.heat = readHeat(*heat);
        }
        if (auto report = top.object("report"))
        {
            scene.report = readReports(*report);
        }
        if (auto forming = top.object("forming"))
        {
            scene.forming = readForming(*forming);
        }
        scene.contact = readContact(top.object("contact").value_or(JsonObject(empty, "contact")), scene.selfCollision,
                                    scene.selfFriction, scene.edgeCollision, scene.keepLayers);
        scene.time = readTime(top.object("integrator").value_or(JsonObject(empty, "integrator")));
        scene.run = readRun(top.object("run").value_or(JsonObject(empty, "run")));
        for (const JsonObject& a : top.objects("script"))
        {
            scene.script.push_back(readAction(a));
            scene.script.back().origin = "script[" + std::to_string(scene.script.size() - 1) + "]";
        }
        checkTemperatures(scene, top);
        scene.output = readOutput(top.object("output").value_or(JsonObject(empty, "output")));
        scene.bullet = readBullet(top.object("bullet").value_or(JsonObject(empty, "bullet")));
        checkRunLength(scene.time.dt, scene.run.duration, "integrator.dt", "run.duration");
        top.raw("expect"); // read by the regression runner
        top.finish();
        checkReferences(scene, top);
        return scene;
    }
    catch (const InputError& e)
    {
        throw InputError(origin + ": " + e.what());
    }
}

namespace
{
/// Turns a relative path value at `holder[key]` into an absolute one under `folder`.
void makeAbsolute(nlohmann::json& holder, const char* key, const std::filesystem::path& folder)
{
    if (holder.is_object() && holder.contains(key) && holder[key].is_string())
    {
        const std::filesystem::path file = holder[key].get<std::string>();
        if (file.is_relative())
        {
            holder[key] = std::filesystem::absolute(folder / file).lexically_normal().string();
        }
    }
}

} // namespace

void makePathsAbsolute(nlohmann::json& document, const std::filesystem::path& folder)
{
    if (document.contains("material"))
    {
        makeAbsolute(document["material"], "file", folder);
    }
    if (document.contains("obstacles") && document["obstacles"].is_array())
    {
        for (nlohmann::json& obstacle : document["obstacles"])
        {
            makeAbsolute(obstacle, "file", folder);
        }
    }
}

namespace
{
/// Whether `text` is valid UTF-8 (no overlong forms, no surrogates, nothing past U+10FFFF).
bool validUtf8(const std::string& text)
{
    std::size_t i = 0;
    while (i < text.size())
    {
        const unsigned char c = static_cast<unsigned char>(text[i]);
        std::size_t length = c < 0x80 ? 1 : (c >> 5) == 0x6 ? 2 : (c >> 4) == 0xE ? 3 : (c >> 3) == 0x1E ? 4 : 0;
        if (length == 0 || i + length > text.size() || (length == 2 && c < 0xC2))
        {
            return false;
        }
        std::uint32_t code = length == 1 ? c : c & (0x7F >> length);
        for (std::size_t k = 1; k < length; ++k)
        {
            const unsigned char next = static_cast<unsigned char>(text[i + k]);
            if ((next & 0xC0) != 0x80)
            {
                return false;
            }
            code = (code << 6) | (next & 0x3F);
        }
        if ((length == 3 && (code < 0x800 || (code >= 0xD800 && code <= 0xDFFF))) ||
            (length == 4 && (code < 0x10000 || code > 0x10FFFF)))
        {
            return false;
        }
        i += length;
    }
    return true;
}

/// `text` with every byte outside printable ASCII as \xNN, for a message about a name that is not UTF-8.
std::string escaped(const std::string& text)
{
    std::string result;
    for (const char c : text)
    {
        const unsigned char byte = static_cast<unsigned char>(c);
        if (byte >= 0x20 && byte < 0x7F)
        {
            result += c;
            continue;
        }
        char hex[8];
        std::snprintf(hex, sizeof(hex), "\\x%02X", unsigned(byte));
        result += hex;
    }
    return result;
}
} // namespace

namespace
{
/// The name of a list item that has one ("heaters", "obstacles"... give their items names), or "".
std::string itemName(const nlohmann::json& item)
{
    return item.is_object() && item.contains("name") && item["name"].is_string() ? item["name"].get<std::string>()
                                                                                 : std::string();
}

/// Prepares `patch` for RFC 7386's merge patch over `base` (objects merge key by key, a null removes a key, lists and
/// values replace): an item of a list that has the name of an item of the base's list at the same place becomes that
/// base item with the patch's item merged over it. A scene that extends another and gives `"heaters": [{"name":
/// "panel", "power": 5000}]` so changes the panel's power and keeps its place and size, where the plain merge patch
/// would put the defaults in their place without a word. The patch's list still decides which items there are and in
/// what order; an item without a name, with a new one, or of another `type` than the base's item of its name (an
/// obstacle of another shape) is taken as given.
void fillNamedItems(const nlohmann::json& base, nlohmann::json& patch)
{
    if (base.is_object() && patch.is_object())
    {
        for (auto entry = patch.begin(); entry != patch.end(); ++entry)
        {
            if (base.contains(entry.key()))
            {
                fillNamedItems(base[entry.key()], entry.value());
            }
        }
        return;
    }
    if (!base.is_array() || !patch.is_array())
    {
        return;
    }
    for (nlohmann::json& item : patch)
    {
        const std::string name = itemName(item);
        const auto match =
            std::find_if(base.begin(), base.end(),
                         [&](const nlohmann::json& candidate) { return !name.empty() && itemName(candidate) == name; });
        if (match == base.end() ||
            (item.contains("type") && match->contains("type") && item["type"] != (*match)["type"]))
        {
            continue;
        }
        fillNamedItems(*match, item);
        nlohmann::json combined = *match;
        combined.merge_patch(item);
        item = std::move(combined);
    }
}

/// The files a chain of "extends" has read so far, outermost first, as given and as the files they are.
struct ExtendsChain
{
    std::vector<std::string> given;
    std::vector<std::filesystem::path> files;
};

nlohmann::json readSceneDocument(const std::string& path, ExtendsChain& chain)
{
    // A scene's path goes into summary.json and the reports, which are UTF-8 JSON and text.
    if (!validUtf8(path))
    {
        throw InputError(escaped(path) + ": the file name is not valid UTF-8 (summary.json records it): rename the "
                                         "file");
    }
    nlohmann::json document = readJsonFile(path);
    if (!document.is_object() || !document.contains("extends"))
    {
        return document;
    }
    // "extends": a base scene this file patches (RFC 7386 merge patch: keys given here replace the base's).
    if (!document["extends"].is_string())
    {
        throw InputError(path + ": extends: expected the path of a base scene file");
    }
    const std::string reference = document["extends"].get<std::string>();
    const std::filesystem::path base = std::filesystem::path(path).parent_path() / reference;
    std::error_code error;
    const std::filesystem::path file = std::filesystem::weakly_canonical(base, error);
    if (error || !std::filesystem::exists(file, error))
    {
        throw InputError(path + ": extends: the base scene '" + reference + "' does not exist (" + base.string() + ")");
    }
    chain.given.push_back(path);
    chain.files.push_back(std::filesystem::weakly_canonical(path, error));
    if (std::find(chain.files.begin(), chain.files.end(), file) != chain.files.end())
    {
        std::string loop;
        for (const std::string& given : chain.given)
        {
            loop += given + " -> ";
        }
        throw InputError(path + ": extends: '" + reference + "' leads back to a file of the chain (a loop: " + loop +
                         base.string() + ")");
    }
    if (chain.files.size() > maxExtendsDepth)
    {
        throw InputError(path + ": extends: more than " + std::to_string(maxExtendsDepth) + " files in the chain");
    }
    nlohmann::json merged = readSceneDocument(base.string(), chain);
    // The base's relative paths (its material file, its meshes) are relative to the base's own folder: make them
    // absolute before merging, so that only the paths this file writes resolve against this file's folder.
    makePathsAbsolute(merged, base.parent_path());
    merged.erase("expect");
    nlohmann::json patch = document;
    patch.erase("extends");
    fillNamedItems(merged, patch);
    merged.merge_patch(patch);
    return merged;
}

} // namespace

nlohmann::json readSceneDocument(const std::string& path)
{
    ExtendsChain chain;
    return readSceneDocument(path, chain);
}

SceneSpec loadScene(const std::string& path)
{
    const nlohmann::json document = readSceneDocument(path);
    return parseScene(document, std::filesystem::path(path).parent_path().string(), path);
}
} // namespace masse::scene
