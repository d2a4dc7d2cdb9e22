#pragma once
/// The obstacles of a scene (the room and the polyhedra) in a Bullet collision world, serving the core's contact
/// solver as its ContactDetector.
///
/// Bullet supplies the broadphase (a btDbvtBroadphase: each mass's reach box is queried against the obstacles'
/// boxes), the mesh's triangle walk (btBvhTriangleMeshShape) and the sweep (btCollisionWorld::convexSweepTest); the
/// nearest point of a convex obstacle or of each nearby triangle of a mesh has a closed form and is computed so
/// (FacePlaneDistance.h, NearestOnFrontFaces.h, ClosestPointOnTriangle.h). The paper's game rule holds by construction:
/// obstacles are static or kinematic and are never tested against one another; only sheet masses are tested.

#include "FacePlanesOfEight.h"
#include "KinematicPath.h"
#include "NearbyTriangles.h"
#include "ObstacleGeometry.h"

#include "core/contact/Contact.h"
#include "core/parallel/PerChunk.h"

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

class btBroadphaseInterface;
class btCollisionConfiguration;
class btCollisionDispatcher;
class btCollisionObject;
class btCollisionWorld;

namespace masse::bridge
{
/// Masses per chunk of contact detection: small, because the work gathers where the sheet meets an obstacle, and
/// small chunks let the threads share that part evenly.
inline constexpr std::size_t detectionChunkSize = 512;

/// An obstacle as the environment takes it: a named solid and where it is over time.
struct ObstacleBody
{
    std::string name;
    ObstacleShape shape;
    KinematicPath path;
};

struct Obstacle
{
    std::string name;
    ObstacleGeometry geometry;
    KinematicPath path;
    std::unique_ptr<btCollisionObject> object;
    bool partOfRoom = false;
    Pose pose;
    Motion motion;
    Real boundingRadius = 0;           ///< m, of the local vertices about the local origin
    int meshSlot = -1;                 ///< a mesh's place among the mesh obstacles (NearbyTriangles), -1 if convex
    Vec3 broadphaseMin = Vec3::Zero(); ///< the box Bullet's broadphase holds for it (world frame, with Bullet's margin)
    Vec3 broadphaseMax = Vec3::Zero();
};

class BulletEnvironment final : public ContactDetector
{
public:
    BulletEnvironment();
    ~BulletEnvironment() override;
    BulletEnvironment(const BulletEnvironment&) = delete;
    BulletEnvironment& operator=(const BulletEnvironment&) = delete;

    /// Adds an obstacle and returns its index; throws InputError naming it for bad geometry, a bad path or a name
    /// already used. `partOfRoom` marks the room's floor, ceiling and walls (outputs leave most of them out).
    int addObstacle(const ObstacleBody& body, bool partOfRoom = false);

    const Obstacle& obstacle(int index) const { return *m_obstacles[std::size_t(index)]; }
    /// Appends keys to a kinematic obstacle's path (a scripted move); keys must come after its last one.
    void extendPath(int index, const std::vector<PoseKey>& keys);
    /// Replaces a kinematic obstacle's path from `time` on: from its pose then, straight to `target` at `speed` (m/s,
    /// > 0), keeping its orientation, then held there (a plug steered live).
    void steer(int index, Real time, const Vec3& target, Real speed);
    /// Index of the obstacle with that name, or -1.
    int findObstacle(const std::string& name) const;

    // ContactDetector
    int obstacleCount() const override { return int(m_obstacles.size()); }
    void setTime(Real time) override;
    void findContacts(const std::vector<Vec3>& x, const std::vector<Real>& reach, Real radius, Real dt,
                      ContactPlaneLists& out) override;
    std::optional<SweepHit> sweep(const Vec3& from, const Vec3& to, Real radius) override;
    SurfaceDistance nearestSurface(const Vec3& x, Real maxDistance) override;
    Vec3 pointVelocity(int obstacle, const Vec3& point, Real dt) override;

private:
    struct Closest
    {
        Real distance; ///< between the sphere's surface and the obstacle's (negative: overlapping)
        Vec3 normal;   ///< from the obstacle toward the sphere's centre
        Vec3 point;    ///< on the obstacle's surface
        int face;
    };
    /// Closest features of one obstacle to a sphere: one for a convex obstacle, up to three distinct ones (by
    /// normal) for a mesh, nearest first. For a mesh, `nearby` (or null) holds the triangles kept near this mass
    /// from an earlier query, used when they cover this one and gathered anew otherwise.
    void closestFeatures(int obstacle, const Vec3& centre, Real radius, Real searchDistance, std::vector<Closest>& out,
                         NearbyTriangles* nearby = nullptr) const;
    /// One chunk of masses in findContacts: what its masses' queries share.
    struct ChunkQuery
    {
        const std::vector<Vec3>& x;
        const std::vector<Real>& reach;
        Real radius;
        Real dt;
        Real obstacleTravel;                    ///< m, the farthest a kinematic obstacle's point moves this frame
        std::vector<FacePlanesOfEight>& eights; ///< per obstacle of `near`, the current eight masses' face planes
        NearbyTriangles* nearby;                ///< per mass, then per mesh slot: its kept triangles
        std::vector<int> near{};                ///< the obstacles whose boxes meet the chunk's
        std::uint8_t batched = 0;               ///< bit s: eights[s] holds near[s]'s planes for the current eight
        std::size_t first = 0;                  ///< the current eight's first mass
        std::vector<Closest> features{};        ///< closestFeatures' answer, reused mass to mass
        bool stillReused = false;               ///< a still mass takes its planes of the last detection (see m_still)
    };
    /// The planes of the masses [begin, end), into `planes` (replacing what it held).
    void findChunkContacts(ChunkQuery& query, std::size_t begin, std::size_t end, std::vector<ContactPlane>& planes);
    /// Whether mass i's position and reach are those of the last detection, which may be reused (m_still).
    bool stillSince(const ChunkQuery& query, std::size_t i) const;
    /// Appends mass i's planes of the chunk's obstacles: from the current eight's face planes where a face plane gives
    /// its nearest point, else from closestFeatures.
    void appendMassPlanes(ChunkQuery& query, std::size_t i, std::vector<ContactPlane>& planes) const;
    /// Copies the obstacle's broadphase box (after it was added or moved).
    static void recordBroadphaseBox(Obstacle& obstacle);
    /// Obstacles whose boxes overlap the box [lo, hi], in index order.
    void candidates(const Vec3& lo, const Vec3& hi, std::vector<int>& out) const;

    std::unique_ptr<btCollisionConfiguration> m_configuration;
    std::unique_ptr<btCollisionDispatcher> m_dispatcher;
    std::unique_ptr<btBroadphaseInterface> m_broadphase;
    std::unique_ptr<btCollisionWorld> m_world;
    std::vector<std::unique_ptr<Obstacle>> m_obstacles;
    Real m_time = 0;
    Real m_fastestKinematic = 0;       ///< m/s, the fastest any kinematic obstacle's point moves now
    std::vector<Motion> m_frameMotion; ///< per obstacle, its mean motion over the frame being detected
    PerChunk<std::vector<FacePlanesOfEight>> m_chunkEights; ///< per chunk, its eights' face planes of each obstacle
    int m_meshObstacles = 0;                                ///< obstacles that are meshes (each has a mesh slot)
    std::vector<NearbyTriangles> m_nearby; ///< mass i's kept triangles of mesh slot s at i * m_meshObstacles + s

    /// A mass's planes depend on its position and reach, the radius and the obstacles alone: among still obstacles, a
    /// mass whose position and reach are the same bits as at the last detection has the same planes, which it takes
    /// from that detection's lists instead of asking the obstacles again (a sheet held on a mould: half the masses of
    /// the vacuum cup and the pressure tray from their first frames in contact on).
    struct StillMasses
    {
        std::vector<Vec3> x;                   ///< per mass, its position at the last detection
        std::vector<Real> reach;               ///< and its reach
        std::vector<std::uint32_t> firstPlane; ///< its planes in its chunk's list: [firstPlane, endPlane)
        std::vector<std::uint32_t> endPlane;
        PerChunk<std::vector<ContactPlane>> planes; ///< each chunk's planes as that detection found them
        Real radius = -1;                           ///< the radius it was made for; negative: nothing to reuse
        std::uint64_t world = 0;                    ///< the obstacles it was made for (m_world's version)
    };
    StillMasses m_still;
    std::uint64_t m_worldVersion = 0; ///< counts changes to the obstacles: added, their paths extended or steered
};
} // namespace masse::bridge
