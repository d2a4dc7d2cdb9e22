#pragma once
/// What the window draws and shows, copied out of the running scene by the simulation thread after each batch of
/// steps (SimulationThread). The window reads only snapshots, never the live scene, so drawing, the panel and picking
/// run at their own rate however long a step takes. No GL: the tests build and read snapshots directly.

#include "MassScalars.h"
#include "ViewerSession.h"

#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace masse::viewer
{
/// The sheet's drawing topology, built once per scene (generation).
struct SheetTopology
{
    std::vector<std::uint32_t> springIndices;    ///< two mass indices per spring
    std::vector<std::uint32_t> surfaceTriangles; ///< the closed outer surface (sheetSurfaceTriangles)
    Real spacing = 0;                            ///< m, the lattice's smallest spacing
    int layers = 1;
    /// Masses every 2^k rows and columns of every layer, k = 1, 2, ... (massesAtStride): what masses mode draws of a
    /// sheet whose masses lie closer together on screen than a couple of pixels.
    std::vector<std::vector<std::uint32_t>> coarseMasses;
    /// The closed surface at the same strides (coarseSurfaceTriangles), for the surface modes.
    std::vector<std::vector<std::uint32_t>> coarseSurfaces;
};

/// An obstacle where it is now, as the renderer and the screen regions need it.
struct ObstacleShape
{
    std::string name;
    bool partOfRoom = false;
    Vec3 position = Vec3::Zero();
    std::vector<Vec3> vertices;          ///< world
    std::vector<std::vector<int>> faces; ///< vertex indices
    std::vector<Vec3> normals;           ///< world, one per face
    std::vector<bool> touched;           ///< per face: a mass touched it during the last step
    bool kinematic = false;              ///< it follows a path (a plug): the process controls steer it
    Vec3 velocity = Vec3::Zero();        ///< m/s, of its origin
    Real temperatureC = 0;               ///< its temperature for contact heat, when `hasTemperature`
    bool hasTemperature = false;
};

/// The forming process as it runs, for the process controls and the HUD (ProcessControls.h).
struct ProcessState
{
    bool forming = false;            ///< the scene has a forming pressure
    Real pressure = 0;               ///< Pa, now
    std::vector<Real> heaterPower;   ///< W per heater when on
    std::size_t recordedActions = 0; ///< actions added while running, which "save run" writes
    bool mousePulled = false;        ///< the mouse pulled a mass since the scene started (a saved run lacks it)
    bool saveable = false;           ///< the scene came from a file (not edited in the panel): it can be saved
};

/// Bullet's twin (--compare) as the ghost draws it.
struct GhostShape
{
    std::vector<Vec3> nodes;
    std::vector<std::uint32_t> links; ///< two node indices per link
    std::vector<bool> touching;
    std::size_t touchingCount = 0;
    Real masseDeepest = 0; ///< m, deepest penetration so far
    Real bulletDeepest = 0;
};

/// The heat side of the panel.
struct HeatState
{
    Real ambientC = 0;
    std::vector<bool> heatersOn;
    Real lowestC = 0;
    Real highestC = 0;
    std::optional<Real> thinnest; ///< m, on material scenes
    Real initialThickness = 0;    ///< m
};

/// Mass flags for colouring.
enum MassFlag : std::uint8_t
{
    massFree = 0,
    massInContact = 1,
    massPinned = 2,
    massInSelfContact = 3, ///< touching another part of the sheet at the last substep (contact.self_collision)
};

struct SceneSnapshot
{
    std::uint64_t generation = 0;    ///< the session's; a new one means a new spec and topology
    std::uint64_t appliedTicket = 0; ///< every command posted with a ticket up to this one has been carried out
    /// Counts the simulation thread's publications (0: made by hand): a snapshot object is reused for later ones, so
    /// the renderer tells a new one from the one it already uploaded by this.
    std::uint64_t sequence = 0;
    std::shared_ptr<const scene::SceneSpec> spec;
    std::shared_ptr<const SheetTopology> topology;

    Real time = 0;
    bool paused = false;
    std::string error;
    std::string notice;
    std::size_t springCount = 0;
    std::size_t touchingCount = 0;
    std::size_t selfTouchingCount = 0; ///< masses touching another part of the sheet (contact.self_collision)
    std::vector<scene::SceneEvent> events;

    std::vector<Vec3> positions;
    std::vector<std::uint8_t> flags; ///< MassFlag per mass
    std::string scalarName;          ///< the scalar `scalar` holds ("" when none was asked for)
    std::vector<float> scalar;
    /// The scalar's fixed colour span on this scene (MassScalar::fixedRange), else none: the values' own.
    std::optional<ScalarRange> scalarFixedRange;
    /// The live section (ViewerSession::setSection) on a material scene: its bottom-layer masses along the line.
    std::vector<scene::SectionPoint> section;
    int sectionAxis = 0; ///< 0: along x, 2: along z
    /// The thinnest mass (any layer) and its thickness in m, on material scenes: marked on the sheet.
    std::optional<std::pair<Index, Real>> thinnest;
    /// Why the scene has no values for the scalar asked for ("" when it has them): e.g. temperature on a scene
    /// without heat.
    std::string scalarMissing;
    /// Every registered scalar the scene lacks, with the reason (the panel greys them out): (name, reason).
    std::vector<std::pair<std::string, std::string>> missingScalars;

    std::vector<ObstacleShape> obstacles;
    std::vector<std::pair<Vec3, Vec3>> grabs; ///< scripted grabs: mass position, target
    std::optional<Index> pickedMass;
    Vec3 pickTarget = Vec3::Zero();
    std::optional<GhostShape> ghost;
    std::optional<HeatState> heat;
    ProcessState process;

    // Totals since the session started, for rates.
    std::uint64_t steps = 0;
    Real stepSeconds = 0;
    bool behind = false; ///< the last batch dropped owed time (slow motion)
};

/// Copies the session's scene into `out` (reusing its storage). `scalar`: the scalar to evaluate ("" for none).
/// The topology and spec are shared with `previous` while the generation is the same.
void captureSnapshot(ViewerSession& session, const MassScalarRegistry& scalars, const std::string& scalar,
                     const SceneSnapshot* previous, SceneSnapshot& out);

/// Why the scene cannot show a scalar, or "" when it can (temperature needs a heat scene, thickness a material).
std::string scalarMissingReason(const scene::Scene& scene, const std::string& scalar);
/// The same from a snapshot's `missingScalars`.
std::string missingScalarReason(const SceneSnapshot& snapshot, const std::string& scalar);
} // namespace masse::viewer
