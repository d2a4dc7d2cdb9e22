#pragma once
/// A running scene: the sheet, its obstacles in Bullet, contact, time stepping, the script, and the events so far.
/// The headless runner, the viewer, the tests and the benchmarks all drive a scene through this class.

#include "scene/RestTracker.h"
#include "scene/SceneSpec.h"
#include "scene/ScriptRunner.h"

#include "bridge/BulletEnvironment.h"

#include "core/Simulator.h"
#include "core/contact/ContactSolver.h"
#include "core/contact/EdgeContact.h"
#include "core/contact/SelfContact.h"
#include "core/material/PressureLoad.h"
#include "core/material/ThermalModel.h"
#include "core/material/ViscoelasticSprings.h"

#include <chrono>
#include <memory>

namespace masse
{
class LayerGap;
class MotionLimit;
} // namespace masse

namespace masse::scene
{
/// Something that happened: "contact" (the first with an obstacle; object = its name), "rest" (object "sheet"),
/// or a script action ("grab", "release", "pin", "unpin", "gravity", "move").
struct SceneEvent
{
    std::string name;
    std::string object;
    Real simTime = 0;  ///< s, simulated
    Real wallTime = 0; ///< s of wall clock since the scene started
};

class Scene
{
public:
    /// Builds everything the spec describes; throws InputError (prefixed with the scene's file) for an obstacle
    /// whose geometry is bad or a mesh that will not load.
    explicit Scene(SceneSpec spec);
    ~Scene();

    /// Advances one step of the scene's dt (the last step of the run, shorter, ends on its duration exactly); returns
    /// what the simulator did.
    StepReport step();
    /// Starts again from the spec (used by the viewer's reset).
    void reset();

    const SceneSpec& spec() const { return m_spec; }
    Real time() const { return m_simulator->time(); }
    std::uint64_t steps() const { return m_steps; }
    Simulator& simulator() { return *m_simulator; }
    const Simulator& simulator() const { return *m_simulator; }
    /// Replaces the simulator's task pool by one of `threads` threads (the spec's engine.threads, kept on reset);
    /// between steps only. Throws InputError for field "threads" when out of range.
    void setThreadCount(int threads);
    MassSpringSystem& system() { return m_simulator->system(); }
    const MassSpringSystem& system() const { return m_simulator->system(); }
    const Lattice& lattice() const { return m_lattice; }
    bridge::BulletEnvironment& environment() { return *m_environment; }
    ContactSolver& contact() { return *m_contact; }
    const ContactSolver& contact() const { return *m_contact; }
    /// The sheet against itself (nullptr unless contact.self_collision is on).
    SelfContact* selfContact() { return m_selfContact.get(); }
    const SelfContact* selfContact() const { return m_selfContact.get(); }
    /// The sheet's edges and triangles against the obstacles' edges and corners (nullptr unless
    /// contact.edge_collision is on).
    EdgeContact* edgeContact() { return m_edgeContact.get(); }
    const EdgeContact* edgeContact() const { return m_edgeContact.get(); }
    const ScriptRunner& script() const { return *m_script; }
    /// The heat model (nullptr without a "heat" section).
    ThermalModel* thermal() { return m_thermal.get(); }
    const ThermalModel* thermal() const { return m_thermal.get(); }
    /// The pressure across the sheet (nullptr without a "forming" section).
    const PressureLoad* pressure() const { return m_pressure.get(); }
    /// Local thickness of the sheet (nullptr without a material); current as of the last frame.
    const SheetThickness* thickness() const;
    /// Switches a heater (by its index in the scene's heat section) on or off, as the script's "heater" action.
    void setHeater(std::size_t heater, bool on);
    bool heaterOn(std::size_t heater) const { return m_heaterOn.at(heater); }
    /// Sets the room air temperature (K), as the script's "ambient" action.
    void setAmbientTemperature(Real kelvin);
    /// W, a heater's power when on (its own, or the last "heater" action's).
    Real heaterPower(std::size_t heater) const { return m_heaterPower.at(heater); }
    /// Pa, the forming pressure's schedule now (0 without a "forming" section).
    Real formingPressure() const;
    /// K, an obstacle's temperature for contact heat (NaN: the air's, or no heat model).
    Real obstacleTemperature(int obstacle) const;

    /// Adds a script action between steps, at or after the scene's time: it fires as a scene file's action at that
    /// time would, at the start of the next frame at or after it. Throws InputError (the action's key: "mass",
    /// "heater"...), adding nothing, for a time in the past or a mass, grab, obstacle or heater the scene lacks.
    void addAction(ScriptAction action);
    /// The actions added since the scene was built (reset forgets them), in the order added.
    const std::vector<ScriptAction>& addedActions() const { return m_addedActions; }
    /// Points the grab labelled `label` from now on straight to `target`, reached `duration` s later (at once for 0);
    /// throws InputError when no grab has that label or the target or duration is not finite.
    void redirectGrab(const std::string& label, const Vec3& target, Real duration);

    const std::vector<SceneEvent>& events() const { return m_events; }
    /// Time of the first event with this name and object, or a negative number.
    Real eventTime(const std::string& name, const std::string& object) const;
    /// At rest by the spec's threshold, held long enough, after the contacts the spec asks for first.
    bool atRest() const { return m_rest.atRest(time()); }
    /// The run is over: its duration is reached, or it stops at rest and is at rest.
    bool finished() const;
    Real kineticEnergy() const;
    /// Script actions that have not fired yet, in the order they will.
    std::vector<const ScriptAction*> pendingActions() const;
    /// Whether an action is still to fire or a scripted motion (a grab's or an obstacle's path) still to end: rest
    /// cannot count yet.
    bool scriptStillMoving() const;
    /// "" or, when the explicit integrator needs more than 1,000 substeps for each of this scene's steps, a warning
    /// with the count that names the integrator to use instead.
    std::string substepWarning() const;

    /// Wall seconds since the scene started (or was reset).
    Real wallSeconds() const;

private:
    void build();
    // The stages of build(), in order. The spec's values were checked as the scene was read; what the core still
    // refuses is named by its key all the same (FieldKeys.h).
    void tearDown();
    Lattice buildSheetLattice() const;
    /// The heat model, if the scene has a "heat" section.
    void buildHeat();
    MassSpringSystem buildSheet(Real startTemperature) const;
    /// m: the most an implicit frame may carry a mass before the motion limit splits it; 0 when it never does.
    Real motionLimit() const;
    /// The Bullet environment (room and obstacles) and the contact solver over it.
    void buildContact();
    /// The material's springs (and the sheet's thickness, when no heat model keeps it), if the scene has a material.
    void buildMaterialSprings(const MassSpringSystem& sheet, Real startTemperature);
    void buildSimulator(MassSpringSystem sheet);
    void addHooks();
    /// The time after which nothing scripted moves: the last action, grab-path key or obstacle-path key.
    static Real scriptedMotionEnd(const SceneSpec& spec);
    /// When one action's motion ends: its time, or its path's last key.
    static Real motionEnd(const ScriptAction& action);
    Real nextStep() const;
    /// Throws InputError when the forming section names a mould that is a mesh with a gap (an edge of one face).
    void requireSealedMould() const;
    void record(const std::string& name, const std::string& object, Real simTime);
    /// The script's actions on what the scene owns: heat, obstacle temperatures, the forming pressure.
    void carryOut(const ScriptAction& action);
    void setObstacleTemperature(int obstacle, Real kelvin);
    void updateRest();

    SceneSpec m_spec;
    Lattice m_lattice;
    std::unique_ptr<bridge::BulletEnvironment> m_environment;
    std::unique_ptr<ContactSolver> m_contact;
    std::unique_ptr<Simulator> m_simulator;
    std::unique_ptr<ScriptRunner> m_script;
    std::unique_ptr<SelfContactBroadphase> m_selfContactPairs;
    std::unique_ptr<SelfContact> m_selfContact;
    std::unique_ptr<EdgeContactDetector> m_edgeContactPairs;
    std::unique_ptr<EdgeContact> m_edgeContact;
    std::unique_ptr<LayerGap> m_layerGap;
    std::unique_ptr<MotionLimit> m_motionLimit;
    std::unique_ptr<ThermalModel> m_thermal;
    std::unique_ptr<ViscoelasticSprings> m_springs;
    std::unique_ptr<SheetThickness> m_thickness; ///< for a material sheet without heat
    std::unique_ptr<PressureLoad> m_pressure;
    std::vector<bool> m_heaterOn;
    std::vector<Real> m_heaterPower;          ///< W per heater when on
    std::vector<ScriptAction> m_addedActions; ///< added while running (addAction), for the guard's bounds
    std::vector<SceneEvent> m_events;
    std::size_t m_contactsSeen = 0;
    std::vector<int> m_restPrerequisites;
    RestTracker m_rest;
    Real m_scriptedMotionEnd = 0; ///< s, when the last scripted action, grab path or obstacle path ends
    std::uint64_t m_steps = 0;
    std::chrono::steady_clock::time_point m_start;
};
} // namespace masse::scene
