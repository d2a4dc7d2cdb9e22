#pragma once
/// Everything a scene file says: the sheet, the environment, the obstacles, contact, time stepping, the run and its
/// script. One description serves the headless runner, the viewer, the comparison with Bullet, the tests and the
/// benchmarks. Keys, units, defaults and ranges: data/scenes/README.md.

#include "scene/FormingSpec.h"
#include "scene/ObstacleSpec.h"
#include "scene/Room.h"

#include "bridge/SoftBodyTwinSettings.h"

#include "core/MassSpringSystem.h"
#include "core/contact/Contact.h"
#include "core/integrate/Integrator.h"
#include "core/integrate/StabilityEstimate.h"
#include "core/lattice/Lattice.h"
#include "core/material/Material.h"
#include "core/material/ThermalModel.h"
#include "core/material/ViscoelasticSprings.h"

#include <any>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace masse::scene
{
/// Masses to pin, by index or by where they are in the lattice.
struct PinSpec
{
    std::vector<Index> masses;      ///< mass indices
    std::vector<int> corners;       ///< 0..3, bottom layer, in Lattice::bottomCorners() order
    std::vector<std::string> edges; ///< "x_min", "x_max", "z_min", "z_max": every layer's masses on that edge
};

struct SheetSpec
{
    LatticeSpec lattice;
    SheetParams params;
    Real repulsion = 0; ///< N m^2, k_r of the compression repulsion (0: off)
    /// Degrees about x, then y, then z (fixed axes), turning the sheet about the centre of its box.
    Vec3 rotationDegrees = Vec3::Zero();
    PinSpec pinned;
    /// Where the lattice's size was last given, for messages about it: the scene's key or a flag ("--size").
    std::string sizeGiven = "sheet.size";
};

/// What the sheet is made of, when it is a real material rather than the paper's spring constants.
struct MaterialSpec
{
    bool enabled = false;
    std::string file; ///< where it was read from ("" if given inline)
    Material material;
    Real thickness = 0.002; ///< m, h0 of the sheet
    SpringModelSettings springs;
};

/// Heat: temperatures, heaters and hot-air zones (needs a material).
struct HeatSpec
{
    bool enabled = false;
    ThermalSettings settings;
    std::vector<std::string> heaterNames;
    std::vector<Real> heaterPower; ///< W when on, per heater
    std::vector<bool> heaterOn;    ///< at the start
    std::vector<std::string> zoneNames;
};

/// The scene's "report" object: each report it names, by its key, with the settings that report read from it
/// (scene/reports/ReportRegistry.h, one entry a report); a report finds its own with reportSettings.
struct ReportSpec
{
    std::map<std::string, std::any, std::less<>> asked;
};

struct EnvironmentSpec
{
    Vec3 gravity = Vec3(0, -standardGravity, 0); ///< m/s^2
    Real airDampingRate = 0;                     ///< 1/s (drag f = -c m v)
    RoomSpec room;
};

struct TimeSpec
{
    IntegratorKind integrator = IntegratorKind::SymplecticEuler;
    Real dt = 0.03;             ///< s, the step asked for (explicit integrators substep it)
    Real stabilitySafety = 0.5; ///< explicit integrators: fraction of the estimated stable step
    ImplicitSettings implicit;
    /// Implicit integrators: the most a mass may move in one solve, in lattice spacings; a frame that would move one
    /// further is split into shorter solves (core/integrate/MotionLimit.h). Unset: 3 in forming scenes, none elsewhere;
    /// 0: none.
    std::optional<Real> maxMotion;
};

/// When the run ends.
struct RunSpec
{
    Real duration = 10;            ///< s of simulated time at most
    bool stopAtRest = true;        ///< stop once at rest (after every other expected stage)
    Real restKineticEnergy = 1e-5; ///< J, the sheet is at rest below this total kinetic energy...
    Real restHold = 0.5;           ///< s ...held this long
    /// Obstacles the sheet must have touched before rest may end the run (the paper's stages: rest comes last).
    std::vector<std::string> restAfterContactWith;
};

/// One scripted action at a time.
struct ScriptAction
{
    enum class Kind
    {
        Grab,    ///< a dynamic spring from a mass to a point that follows `path`
        Release, ///< removes a grab's spring
        Pin,
        Unpin,
        Gravity,  ///< sets gravity to `vector`
        Move,     ///< moves a kinematic obstacle along `obstaclePath` (times absolute)
        Heater,   ///< switches a heater on or off (`heater`, `on`), at `power` W when given
        Ambient,  ///< sets the room air temperature (`temperature`, K)
        Pressure, ///< the forming pressure goes to `pressure` Pa over `ramp` s and holds, in place of the schedule
        Steer,    ///< a kinematic obstacle goes from where it is straight to `target` at `speed`, in place of its path
        ObstacleTemperature, ///< sets an obstacle's temperature (`obstacle`, `temperature`, K)
    };
    Kind kind = Kind::Grab;
    Real time = 0;      ///< s
    std::string label;  ///< names a grab, for its release and in events
    std::string origin; ///< where it was given, for messages: "script[2]" in a file; empty for one added while running
    // Grab
    bool grabNearest = false; ///< grab the mass nearest `point` (else `mass`)
    Index mass = 0;
    Vec3 point = Vec3::Zero();
    std::vector<std::pair<Real, Vec3>> path; ///< (time s, target m); the first key defaults to the grab's time
    Real stiffness = 5;                      ///< N/m
    Real damping = 0.05;                     ///< N s/m
    Real maxForce = 1;                       ///< N, the pull's cap
    // Pin / Unpin
    PinSpec masses;
    // Gravity
    Vec3 vector = Vec3::Zero();
    // Move
    std::string obstacle;
    std::vector<bridge::PoseKey> obstaclePath;
    // Heater, Ambient, ObstacleTemperature
    std::string heater;
    bool on = true;
    Real power = -1;           ///< W; below 0: the heater's own from the heat section
    Real temperature = 293.15; ///< K
    // Pressure
    Real pressure = 0; ///< Pa
    Real ramp = 0;     ///< s
    // Steer (and `obstacle`)
    Vec3 target = Vec3::Zero(); ///< m
    Real speed = 0;             ///< m/s
};

/// What the outputs of a run contain.
struct OutputSpec
{
    int framesEvery = 0;              ///< write the sheet every k steps (0: never)
    std::vector<std::string> formats; ///< "vtp", "obj"
    bool objSprings = false;          ///< OBJ frames also hold every spring as a line ("l a b")
};

/// The scene's Bullet soft-body twin, for `masse compare` (the top-level "bullet" object). Every key is optional;
/// what is left out is derived from the sheet so that both engines describe the same material (see
/// bridge/SoftBodyTwinSettings.h for the derivations, which takes every key but "collisions" and "calibrate"). Keys,
/// units, defaults and ranges:
///   "kLST"          dimensionless, (0, 1]; default: per link, from its spring's k_s by the one-link formula
///   "kDP"           dimensionless, [0, 1); default: 1 - exp(-c h), MaSSE's air drag c over one substep h
///   "kDF"           dimensionless, [0, 1]; default: contact.friction (clamped to 1), 1 sticky, 0 frictionless
///   "kCHR"          dimensionless, [0, 1]; default 1 (contact hardness against dynamic bodies)
///   "kKHR"          dimensionless, [0, 1]; default 1 (contact hardness against static and kinematic obstacles;
///                   Bullet's own default 0.1 lets a sheet sink through a box at dt = 0.03 s)
///   "margin"        m, (0, 1]; default: contact.radius
///   "piterations"   position-solver passes per substep, whole number in [1, 1000]; default 4
///   "substeps"      Bullet steps per scene step, whole number in [1, 10000]; default 1 (h = dt / substeps)
///   "sdf_cell_size" m, [0.001, 1]; default 0.25 (cell of Bullet's sparse signed-distance cache)
///   "collisions"    "SDF_RS" only (the default); CL_RS and SDF_RD* are refused with the reason
///   "calibrate"     true or false, default false: measure kLST instead (calibrateLinearStiffness: the sheet clamped
///                   on its two x edges settles in both engines and one kLST is bisected until the sags match);
///                   not together with "kLST"
struct BulletSpec
{
    bridge::SoftBodyTwinSettings settings;
    std::string collisions = "SDF_RS"; ///< Bullet's fCollision name; the twin supports this one only
    bool calibrate = false;
};

/// How the engine runs a scene, chosen by the program that runs it, never by the scene file: the `masse` command takes
/// them from --threads and its environment (EngineEnvironment.h), the Python module from masse.set_threads and the
/// same environment, a test or an embedding program sets them.
struct EngineSettings
{
    /// Threads of the scene's task pool, the calling thread included: the same bits at any count.
    int threads = 1;
    /// The explicit integrators' stable step: results hold for the power estimate (see StabilityMethod).
    StabilityMethod stability = StabilityMethod::Power;
};

struct SceneSpec
{
    std::string name;
    std::string description;
    std::string path; ///< the file it was read from ("" if built in code)
    SheetSpec sheet;
    EnvironmentSpec environment;
    std::vector<ObstacleSpec> obstacles;
    /// K per obstacle, for heat exchange on contact (NaN: at the air's temperature, as the room's walls are).
    std::vector<Real> obstacleTemperature;
    /// Per obstacle, its own contact response ("contact" in the obstacle; `own` false: the scene's).
    std::vector<ObstacleContact> obstacleContact;
    MaterialSpec material;
    HeatSpec heat;
    ReportSpec report;
    FormingSpec forming; ///< pressure across the sheet (vacuum and pressure forming)
    ContactSettings contact;
    /// The sheet against itself ("contact.self_collision", off by default); its radius is contact.radius.
    bool selfCollision = false;
    Real selfFriction = 0.3; ///< "contact.self_friction": Coulomb mu between sheet and sheet
    /// The sheet's surface edges and triangles against the obstacles' sharp edges and corners
    /// ("contact.edge_collision", off by default).
    bool edgeCollision = false;
    /// Each upper-layer mass of a sheet with a material kept above the cell beneath it by its rest height times the
    /// local thickness ratio ("contact.keep_layers"; core/contact/LayerGap.h). Unset: off.
    std::optional<bool> keepLayers;
    TimeSpec time;
    RunSpec run;
    std::vector<ScriptAction> script;
    OutputSpec output;
    BulletSpec bullet;
    EngineSettings engine;
};
} // namespace masse::scene
