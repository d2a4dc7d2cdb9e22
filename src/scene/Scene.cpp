#include "scene/Scene.h"

#include "scene/GuardBounds.h"
#include "scene/MemoryBudget.h"
#include "scene/Pins.h"
#include "scene/SceneFile.h"
#include "scene/json/FieldKeys.h"

#include "bridge/MeshTopology.h"
#include "bridge/SelfContactTree.h"
#include "bridge/SheetEdgeTree.h"

#include "core/Format.h"
#include "core/InputError.h"
#include "core/contact/LayerGap.h"
#include "core/forces/Energy.h"
#include "core/integrate/MotionLimit.h"
#include "core/material/MaterialSheet.h"
#include "core/material/MembraneStiffness.h"

#include <algorithm>
#include <limits>

namespace masse::scene
{
namespace
{
/// Substeps per step above which a run says, before it starts, that it will be slow.
constexpr int warnedSubsteps = 1000;
/// The most solves the motion limit splits a frame into: a sheet slammed onto the mould in one frame (the tray's
/// first, at 3.5 km/s^2) takes that many and no more, and the layer floor and the contact catch the rest.
constexpr int maxSolvesForMotion = 64;

/// Runs a check of the sheet's size (its lattice, the memory it needs) under the scene's names; an error of a size
/// given elsewhere than the scene file (`--size`, the viewer's panel, the paper's sizes) names where it came from
/// instead of `sheet.size`, and Scene::build does not put it under the file's name.
template <typename Check> void checkSheetSize(const SceneSpec& spec, Check&& check)
{
    try
    {
        check();
    }
    catch (const InputError& e)
    {
        if (spec.sheet.sizeGiven != "sheet.size" && keyOf(latticeKeys, e.field()) == "size")
        {
            throw InputError(spec.sheet.sizeGiven, e.problem());
        }
        throw InputError(messageUnder("sheet", latticeKeys, e));
    }
}
} // namespace

Scene::Scene(SceneSpec spec) : m_spec(std::move(spec))
{
    build();
}

Scene::~Scene() = default;

void Scene::reset()
{
    build();
}

void Scene::build()
{
    tearDown();
    m_addedActions.clear();
    try
    {
        // Again: --size (or the paper's sizes, or the viewer's panel) may have made the sheet smaller than the
        // masses the scene names; the engine would index past its arrays.
        checkMassIndices(m_spec);
        // A sheet that cannot fit in memory is refused before anything is allocated for it.
        checkSheetSize(m_spec, [&] { checkMemory(m_spec); });
        m_lattice = buildSheetLattice();
        const Real startTemperature =
            m_spec.heat.enabled ? m_spec.heat.settings.initialTemperature : m_spec.material.springs.initialTemperature;
        buildHeat();
        MassSpringSystem sheet = buildSheet(startTemperature);
        buildContact();
        buildMaterialSprings(sheet, startTemperature);
        buildSimulator(std::move(sheet));
        addHooks();
        // A step the integrator cannot take is bad input: found here, before any output is written, not at the first
        // step.
        checkUnder("integrator", integratorKeys, [&] { m_simulator->substepsFor(m_spec.time.dt); });
    }
    catch (const InputError& e)
    {
        if (m_spec.sheet.sizeGiven != "sheet.size" && e.field() == m_spec.sheet.sizeGiven)
        {
            throw; // a size from outside the file (checkSheetSize)
        }
        throw InputError((m_spec.path.empty() ? m_spec.name : m_spec.path) + ": " + e.what());
    }
    m_scriptedMotionEnd = scriptedMotionEnd(m_spec);
    m_restPrerequisites.clear();
    for (const std::string& name : m_spec.run.restAfterContactWith)
    {
        m_restPrerequisites.push_back(m_environment->findObstacle(name));
    }
    m_start = std::chrono::steady_clock::now();
}

void Scene::tearDown()
{
    // In dependency order: the hooks and the solver before what they refer to.
    m_pressure.reset();
    m_springs.reset();
    m_thermal.reset();
    m_thickness.reset();
    m_script.reset();
    m_edgeContact.reset();
    m_layerGap.reset();
    m_edgeContactPairs.reset();
    m_selfContact.reset();
    m_selfContactPairs.reset();
    m_simulator.reset();
    m_contact.reset();
    m_environment.reset();
    m_events.clear();
    m_contactsSeen = 0;
    m_rest = RestTracker(m_spec.run.restKineticEnergy, m_spec.run.restHold);
    m_steps = 0;
}

Lattice Scene::buildSheetLattice() const
{
    Lattice lattice;
    checkSheetSize(m_spec, [&] { lattice = buildLattice(m_spec.sheet.lattice); });
    if (m_spec.sheet.rotationDegrees != Vec3::Zero())
    {
        const Vec3 centre = 0.5 * (m_spec.sheet.lattice.minCorner + m_spec.sheet.lattice.maxCorner);
        const auto turn = rotationFromDegrees(m_spec.sheet.rotationDegrees);
        for (Vec3& x : lattice.position)
        {
            x = centre + turn * (x - centre);
        }
    }
    return lattice;
}

void Scene::buildHeat()
{
    if (!m_spec.heat.enabled)
    {
        return;
    }
    const MaterialSpec& material = m_spec.material;
    checkUnder("heat", thermalKeys,
               [&]
               {
                   m_thermal = std::make_unique<ThermalModel>(m_lattice, material.material, material.thickness,
                                                              m_spec.heat.settings);
               });
    m_heaterOn = m_spec.heat.heaterOn;
    m_heaterPower = m_spec.heat.heaterPower;
}

MassSpringSystem Scene::buildSheet(Real startTemperature) const
{
    const MaterialSpec& material = m_spec.material;
    MassSpringSystem sheet;
    if (material.enabled)
    {
        checkUnder("material", materialSheetKeys,
                   [&]
                   {
                       sheet = makeMaterialSheet(m_lattice, material.material, material.thickness, startTemperature,
                                                 material.springs.dampingRatio);
                   });
    }
    else
    {
        checkUnder("sheet", sheetKeys, [&] { sheet = makeSheet(m_lattice, m_spec.sheet.params); });
    }
    sheet.forces.gravity = m_spec.environment.gravity;
    sheet.forces.airDamping = m_spec.environment.airDampingRate;
    sheet.forces.repulsion = m_spec.sheet.repulsion;
    for (Index i : resolvePins(m_spec.sheet.pinned, m_lattice))
    {
        sheet.particles.setPinned(i, true);
    }
    return sheet;
}

void Scene::buildMaterialSprings(const MassSpringSystem& sheet, Real startTemperature)
{
    const MaterialSpec& material = m_spec.material;
    if (!material.enabled)
    {
        return;
    }
    SpringModelSettings springSettings = material.springs;
    springSettings.initialTemperature = startTemperature;
    checkUnder("material", materialSheetKeys,
               [&]
               {
                   m_springs = std::make_unique<ViscoelasticSprings>(
                       sheet, stiffnessPerModulus(m_lattice, material.thickness), material.material, springSettings);
                   if (!m_thermal)
                   {
                       m_thickness = std::make_unique<SheetThickness>(m_lattice, material.thickness);
                   }
               });
}

Real Scene::motionLimit() const
{
    // Forming scenes load a sheet at rest hard enough to throw it across cells in one solve, and more cells the finer
    // the lattice. 3 spacings splits the shipped scenes at their own sizes in their first frame and a few after it;
    // 1 splits the vacuum cup's early frames into as many as 8 and leaves its bottom 3% thicker.
    const Real maxMotion = m_spec.time.maxMotion.value_or(m_spec.forming.enabled ? Real(3) : Real(0));
    const Real spacing = m_lattice.smallerSpacing();
    return maxMotion > 0 && spacing > 0 && !isExplicit(m_spec.time.integrator) ? maxMotion * spacing : Real(0);
}

void Scene::buildContact()
{
    m_environment = std::make_unique<bridge::BulletEnvironment>();
    addRoom(*m_environment, m_spec.environment.room);
    for (const ObstacleSpec& obstacle : m_spec.obstacles)
    {
        m_environment->addObstacle(obstacleBody(obstacle));
    }
    ContactSettings contact = m_spec.contact;
    contact.drivenReach = motionLimit();
    contact.perObstacle.assign(std::size_t(m_environment->obstacleCount()), ObstacleContact{});
    for (std::size_t k = 0; k < m_spec.obstacles.size() && k < m_spec.obstacleContact.size(); ++k)
    {
        contact.perObstacle[std::size_t(m_environment->findObstacle(m_spec.obstacles[k].name))] =
            m_spec.obstacleContact[k];
    }
    checkUnder("contact", contactKeys, [&] { m_contact = std::make_unique<ContactSolver>(*m_environment, contact); });
}

void Scene::buildSimulator(MassSpringSystem sheet)
{
    SimulatorSettings settings;
    settings.integrator = m_spec.time.integrator;
    settings.implicit = m_spec.time.implicit;
    settings.stabilitySafety = m_spec.time.stabilitySafety;
    settings.stabilityMethod = m_spec.engine.stability;
    settings.threads = m_spec.engine.threads;
    m_simulator = std::make_unique<Simulator>(std::move(sheet), settings);
    // The heat model publishes its own thickness every frame; without one the springs follow this one.
    m_simulator->context().thickness = m_thickness.get();
    m_simulator->setContactSolver(m_contact.get());
    const std::vector<Real>& masses = m_simulator->system().particles.mass;
    m_simulator->guard().setSettings(
        guardSettings(m_spec, masses.empty() ? Real(1) : *std::min_element(masses.begin(), masses.end())));
}

void Scene::addHooks()
{
    // In this order: the script first (its actions change what the models see), the heat model before the springs
    // (it publishes the temperatures they read), the pressure last.
    m_script = std::make_unique<ScriptRunner>(
        m_spec.script, m_lattice, *m_environment,
        [this](const std::string& name, const std::string& object, Real t) { record(name, object, t); },
        [this](const ScriptAction& action) { carryOut(action); });
    m_simulator->addHook(m_script.get());
    if (m_spec.selfCollision)
    {
        // Right after the script, so that it runs after the obstacle contact of every substep and before the models
        // that read the positions.
        SelfContactSettings self;
        self.radius = m_spec.contact.radius;
        self.friction = m_spec.selfFriction;
        m_selfContactPairs = std::make_unique<bridge::SelfContactTree>();
        checkUnder("contact", selfContactKeys,
                   [&] { m_selfContact = std::make_unique<SelfContact>(m_lattice, *m_selfContactPairs, self); });
        m_simulator->addHook(m_selfContact.get());
    }
    if (m_spec.edgeCollision)
    {
        // After the self-contact, so that in every substep the obstacles have the last word.
        m_edgeContactPairs = std::make_unique<bridge::SheetEdgeTree>(*m_environment);
        m_edgeContact = std::make_unique<EdgeContact>(m_lattice, *m_edgeContactPairs, m_contact->settings());
        m_simulator->addHook(m_edgeContact.get());
    }
    if (const Real motion = motionLimit(); motion > 0)
    {
        m_motionLimit = std::make_unique<MotionLimit>(motion, maxSolvesForMotion);
        m_simulator->addHook(m_motionLimit.get());
    }
    // On by default where a pressure presses the layers together against a mould (LayerGap.h says why not on a free
    // sheet); contact.keep_layers sets it either way.
    if (m_spec.keepLayers.value_or(m_spec.forming.enabled) && m_spec.material.enabled && m_lattice.spec.layers > 1)
    {
        // Before the heat model and the springs: they read the corrected positions' lengths and thicknesses.
        m_layerGap = std::make_unique<LayerGap>(m_lattice);
        m_layerGap->setContactSolver(m_contact.get());
        m_simulator->addHook(m_layerGap.get());
    }
    if (m_thermal)
    {
        // Obstacles exchange heat at their own temperature; the room's walls and obstacles without one (NaN) are
        // at the air's, and follow it when an "ambient" action changes it.
        std::vector<Real> obstacleTemperature(std::size_t(m_environment->obstacleCount()),
                                              std::numeric_limits<Real>::quiet_NaN());
        for (std::size_t k = 0; k < m_spec.obstacles.size(); ++k)
        {
            obstacleTemperature[std::size_t(m_environment->findObstacle(m_spec.obstacles[k].name))] =
                m_spec.obstacleTemperature[k];
        }
        m_thermal->setObstacleTemperatures(obstacleTemperature);
        m_simulator->addHook(m_thermal.get());
    }
    if (m_springs)
    {
        m_simulator->addHook(m_springs.get());
    }
    if (m_spec.forming.enabled)
    {
        requireSealedMould();
        checkUnder(
            "forming", pressureKeys,
            [&] { m_pressure = std::make_unique<PressureLoad>(m_lattice, PressureSchedule(m_spec.forming.pressure)); });
        m_pressure->setSealing(m_spec.forming.seal);
        m_simulator->addHook(m_pressure.get());
    }
}

Real Scene::scriptedMotionEnd(const SceneSpec& spec)
{
    Real end = 0;
    for (const ObstacleSpec& obstacle : spec.obstacles)
    {
        if (!obstacle.path.empty())
        {
            end = std::max(end, obstacle.path.back().time);
        }
    }
    for (const ScriptAction& action : spec.script)
    {
        end = std::max(end, motionEnd(action));
    }
    return end;
}

Real Scene::motionEnd(const ScriptAction& action)
{
    Real end = action.time;
    if (!action.path.empty())
    {
        end = std::max(end, action.path.back().first);
    }
    if (!action.obstaclePath.empty())
    {
        end = std::max(end, action.obstaclePath.back().time);
    }
    return end;
}

void Scene::requireSealedMould() const
{
    if (m_spec.forming.mould.empty())
    {
        return;
    }
    const bridge::Obstacle& mould = m_environment->obstacle(m_environment->findObstacle(m_spec.forming.mould));
    const auto spec = std::find_if(m_spec.obstacles.begin(), m_spec.obstacles.end(),
                                   [&](const ObstacleSpec& o) { return o.name == mould.name; });
    // A mould among the room's walls is a box; any other is a scene's obstacle, whose shape says whether it is closed.
    if (spec == m_spec.obstacles.end() || spec->shape.entry->closed)
    {
        return;
    }
    std::vector<std::vector<int>> faces;
    for (const bridge::Face& face : mould.geometry.faces)
    {
        faces.push_back(face.vertices);
    }
    if (const auto open = bridge::findOpenEdge(faces))
    {
        const std::string file = spec->shape.file();
        throw InputError("forming.mould: obstacle '" + mould.name + "'" + (file.empty() ? "" : " (" + file + ")") +
                         " is not a closed surface: the edge between vertices " + std::to_string(open->a + 1) +
                         " and " + std::to_string(open->b + 1) + " belongs to " + std::to_string(open->faces) +
                         " face(s) instead of 2, so the sheet cannot seal the cavity over its rim");
    }
}

void Scene::addAction(ScriptAction action)
{
    if (!(action.time >= time() - 1e-9))
    {
        throw InputError("time", "must be at or after the scene's time, " + formatNumber(time()) + " s (got " +
                                     formatNumber(action.time) + ")");
    }
    if (action.kind == ScriptAction::Kind::Grab && action.path.empty())
    {
        throw InputError("path", "a grab needs a path of at least one {\"time\", \"position\"} key");
    }
    ScriptTargets targets;
    targets.masses = system().massCount();
    for (int k = 0; k < m_environment->obstacleCount(); ++k)
    {
        targets.obstacles.push_back(m_environment->obstacle(k).name);
    }
    for (const ObstacleSpec& o : m_spec.obstacles)
    {
        if (!o.isKinematic())
        {
            targets.staticObstacles.push_back(o.name);
        }
    }
    targets.grabs = m_script->grabLabels();
    targets.heaters = m_spec.heat.heaterNames;
    targets.heat = m_thermal != nullptr;
    targets.forming = m_pressure != nullptr;
    checkScriptAction(action, targets);
    // The guard's bounds from the script with this action in it, as a scene file holding it would have had them: a
    // faster plug or a stronger pressure than the file's own is not taken for a divergence.
    m_addedActions.push_back(action);
    SceneSpec withAdded = m_spec;
    withAdded.script.insert(withAdded.script.end(), m_addedActions.begin(), m_addedActions.end());
    const std::vector<Real>& masses = system().particles.mass;
    m_simulator->guard().setSettings(
        guardSettings(withAdded, masses.empty() ? Real(1) : *std::min_element(masses.begin(), masses.end())));
    // Rest counts from the end of every scripted motion, this one's included.
    m_scriptedMotionEnd = std::max(m_scriptedMotionEnd, motionEnd(action));
    m_script->add(std::move(action));
}

void Scene::redirectGrab(const std::string& label, const Vec3& target, Real duration)
{
    if (!target.allFinite())
    {
        throw InputError("target", "must be a finite point");
    }
    if (!(duration >= 0 && duration <= limits::maxDuration))
    {
        throw InputError("duration", "must be a number of seconds in [0, " + formatNumber(limits::maxDuration) +
                                         "] (got " + formatNumber(duration) + ")");
    }
    if (!m_script->redirectGrab(system(), label, target, time(), duration))
    {
        throw InputError("grab", "no grab is labelled '" + label + "'");
    }
    m_scriptedMotionEnd = std::max(m_scriptedMotionEnd, time() + duration);
}

const SheetThickness* Scene::thickness() const
{
    if (m_thermal)
    {
        return &m_thermal->sheetThickness();
    }
    return m_thickness.get();
}

void Scene::setHeater(std::size_t heater, bool on)
{
    if (!m_thermal || heater >= m_heaterOn.size())
    {
        return;
    }
    m_heaterOn[heater] = on;
    ThermalSettings settings = m_thermal->settings();
    settings.heaters[heater].power = on ? m_heaterPower[heater] : Real(0);
    m_thermal->setSettings(settings);
}

void Scene::carryOut(const ScriptAction& action)
{
    switch (action.kind)
    {
    case ScriptAction::Kind::Ambient:
        setAmbientTemperature(action.temperature);
        return;
    case ScriptAction::Kind::Heater:
    {
        const auto& names = m_spec.heat.heaterNames;
        const auto heater = std::size_t(std::find(names.begin(), names.end(), action.heater) - names.begin());
        if (action.power >= 0 && heater < m_heaterPower.size())
        {
            m_heaterPower[heater] = action.power;
        }
        setHeater(heater, action.on);
        return;
    }
    case ScriptAction::Kind::ObstacleTemperature:
        setObstacleTemperature(m_environment->findObstacle(action.obstacle), action.temperature);
        return;
    case ScriptAction::Kind::Pressure:
        if (m_pressure)
        {
            // From the pressure now to the new one over the ramp, then held: the rest of the schedule is replaced.
            const Real now = time();
            std::vector<PressureKey> keys = {{now, m_pressure->schedule().at(now)}};
            keys.push_back({action.ramp > 0 ? now + action.ramp : now, action.pressure});
            if (!(keys.back().time > now))
            {
                keys.erase(keys.begin());
            }
            m_pressure->setSchedule(PressureSchedule(std::move(keys)));
        }
        return;
    default:
        return;
    }
}

void Scene::setObstacleTemperature(int obstacle, Real kelvin)
{
    if (!m_thermal || obstacle < 0)
    {
        return;
    }
    std::vector<Real> temperatures = m_thermal->obstacleTemperatures();
    temperatures.resize(std::max(temperatures.size(), std::size_t(obstacle) + 1),
                        std::numeric_limits<Real>::quiet_NaN());
    temperatures[std::size_t(obstacle)] = kelvin;
    m_thermal->setObstacleTemperatures(std::move(temperatures));
}

Real Scene::formingPressure() const
{
    return m_pressure ? m_pressure->schedule().at(time()) : Real(0);
}

Real Scene::obstacleTemperature(int obstacle) const
{
    if (!m_thermal || obstacle < 0 || std::size_t(obstacle) >= m_thermal->obstacleTemperatures().size())
    {
        return std::numeric_limits<Real>::quiet_NaN();
    }
    return m_thermal->obstacleTemperatures()[std::size_t(obstacle)];
}

void Scene::setAmbientTemperature(Real kelvin)
{
    if (!m_thermal)
    {
        return;
    }
    ThermalSettings settings = m_thermal->settings();
    settings.airTemperature = kelvin;
    m_thermal->setSettings(settings);
}

void Scene::setThreadCount(int threads)
{
    m_simulator->setThreadCount(threads);
    m_spec.engine.threads = threads;
}

Real Scene::wallSeconds() const
{
    return std::chrono::duration<Real>(std::chrono::steady_clock::now() - m_start).count();
}

void Scene::record(const std::string& name, const std::string& object, Real simTime)
{
    m_events.push_back({name, object, simTime, wallSeconds()});
}

Real Scene::eventTime(const std::string& name, const std::string& object) const
{
    for (const SceneEvent& e : m_events)
    {
        if (e.name == name && e.object == object)
        {
            return e.simTime;
        }
    }
    return -1;
}

Real Scene::kineticEnergy() const
{
    const PoolScope threads(m_simulator->pool());
    return masse::kineticEnergy(system().particles);
}

Real Scene::nextStep() const
{
    // The last step of a run ends on its duration exactly: --duration 0.1 at dt = 0.03 s is three steps and one of
    // 0.01 s. A remainder within rounding of a whole step is taken as the whole step.
    const Real remaining = m_spec.run.duration - time();
    const Real dt = m_spec.time.dt;
    return remaining > 1e-9 && remaining < dt * (1 - 1e-9) ? remaining : dt;
}

StepReport Scene::step()
{
    const PoolScope threads(m_simulator->pool()); // the rest test's energy too
    StepReport report;
    try
    {
        report = m_simulator->step(nextStep());
    }
    catch (const InputError& e)
    {
        // A grab's spring joins the stability estimate when it fires: a step that then needs more substeps than the
        // integrator takes is that grab's doing, and the message names it where the scene gave it.
        const std::vector<const ScriptAction*>& grabs = m_script->grabsFiredThisFrame();
        if (e.field() != "dt" || grabs.empty())
        {
            throw;
        }
        const ScriptAction& grab = *grabs.back();
        throw InputError((m_spec.path.empty() ? m_spec.name : m_spec.path) + ": " +
                         (grab.origin.empty() ? std::string() : grab.origin + ".stiffness: ") + "the grab" +
                         (grab.label.empty() ? std::string() : " '" + grab.label + "'") + " of " +
                         formatNumber(grab.stiffness) + " N/m" + (grab.origin.empty() ? " added while running" : "") +
                         ", firing at t = " + formatNumber(time()) + " s, makes the step too stiff: " + e.problem());
    }
    ++m_steps;
    const std::vector<ContactEvent>& contacts = m_contact->report().firstContacts();
    for (; m_contactsSeen < contacts.size(); ++m_contactsSeen)
    {
        const ContactEvent& c = contacts[m_contactsSeen];
        record("contact", m_environment->obstacle(c.obstacle).name, c.time);
    }
    updateRest();
    return report;
}

void Scene::updateRest()
{
    if (!m_spec.run.stopAtRest)
    {
        return; // rest means something only to a scene that waits for it
    }
    // A sheet that rests before its script is done (an action still to fire, a grab or an obstacle still to move)
    // is only waiting: rest counts from the end of the last scripted motion.
    bool ready = !scriptStillMoving();
    for (int obstacle : m_restPrerequisites)
    {
        ready = ready && m_contact->report().everTouched(obstacle);
    }
    if (m_rest.update(time(), ready ? kineticEnergy() : Real(0), ready))
    {
        record("rest", "sheet", m_rest.since());
    }
}

bool Scene::scriptStillMoving() const
{
    if (!m_script->pending().empty() || time() < m_scriptedMotionEnd - 1e-9)
    {
        return true;
    }
    // A steered obstacle's path ends where the steer took it, known only once the steer has fired.
    for (int k = 0; k < m_environment->obstacleCount(); ++k)
    {
        const bridge::KinematicPath& path = m_environment->obstacle(k).path;
        if (path.isKinematic() && time() < path.keys.back().time - 1e-9)
        {
            return true;
        }
    }
    return false;
}

std::vector<const ScriptAction*> Scene::pendingActions() const
{
    return m_script->pending();
}

std::string Scene::substepWarning() const
{
    if (!isExplicit(m_spec.time.integrator))
    {
        return "";
    }
    const int substeps = m_simulator->substepsFor(m_spec.time.dt);
    if (substeps <= warnedSubsteps)
    {
        return "";
    }
    return "the " + std::string(integratorName(m_spec.time.integrator)) + " integrator needs " +
           std::to_string(substeps) + " substeps for each " + formatNumber(m_spec.time.dt) +
           " s step (this sheet's stable step is " + formatNumber(m_spec.time.dt / Real(substeps)) +
           " s), so this run will be slow; the implicit integrator takes the step whole: \"integrator\": {\"type\": "
           "\"implicit\"} (or --integrator implicit)";
}

bool Scene::finished() const
{
    return time() >= m_spec.run.duration - 1e-9 || (m_spec.run.stopAtRest && m_rest.rested());
}
} // namespace masse::scene
