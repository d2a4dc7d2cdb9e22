#include "BulletEnvironment.h"

#include "BulletMath.h"
#include "FacePlaneDistance.h"
#include "FacePlanesOfEight.h"
#include "NearestOnFrontFaces.h"
#include "NearestOnTrianglesOfEight.h"

#include "core/InputError.h"
#include "core/contact/ClosestPointOnTriangle.h"
#include "core/parallel/TaskPool.h"

#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletCollision/CollisionDispatch/btCollisionObject.h>
#include <BulletCollision/CollisionDispatch/btCollisionWorld.h>
#include <BulletCollision/CollisionDispatch/btDefaultCollisionConfiguration.h>
#include <BulletCollision/CollisionShapes/btBvhTriangleMeshShape.h>
#include <BulletCollision/CollisionShapes/btSphereShape.h>

#include <algorithm>
#include <limits>

namespace masse::bridge
{
namespace
{
/// The radius of the sphere that probes for the nearest surface of a solid (the search takes a sphere): small enough
/// not to matter.
constexpr Real probeRadius = 1e-6;

/// Bullet's default pools hold 4,096 contact manifolds and 4,096 collision algorithms, zeroed when made: about 30%
/// of a small sweep case's time goes to that. MaSSE never lets Bullet pair obstacles with each other (only queries
/// and sweeps), so a few of each are plenty; Bullet takes more from the heap should it ever need them.
btDefaultCollisionConstructionInfo smallPools()
{
    btDefaultCollisionConstructionInfo info;
    info.m_defaultMaxPersistentManifoldPoolSize = 32;
    info.m_defaultMaxCollisionAlgorithmPoolSize = 32;
    return info;
}

/// Collects the obstacle indices of broadphase proxies overlapping a box.
struct CandidateCollector : btBroadphaseAabbCallback
{
    std::vector<int>* out;
    bool process(const btBroadphaseProxy* proxy) override
    {
        const auto* object = static_cast<const btCollisionObject*>(proxy->m_clientObject);
        out->push_back(object->getUserIndex());
        return true;
    }
};

/// A triangle near a sphere, in the mesh's own frame: how far the sphere's surface is from it, the direction from its
/// nearest point to the centre, that point, and the triangle.
struct NearTriangle
{
    Real distance;
    Vec3 normal;
    Vec3 point;
    int triangle;
};

/// Nearer first, ties by triangle: the order that picks a mass's planes, whatever order the triangles come in.
bool nearer(const NearTriangle& a, const NearTriangle& b)
{
    return a.distance < b.distance || (a.distance == b.distance && a.triangle < b.triangle);
}

/// Tests one triangle of a mesh against a sphere, in the mesh's own frame (the sphere's centre is taken there; the few
/// answers kept are turned back into the world by the caller). On a finely faceted mould (a rounded rim in many facets)
/// most triangles a walk hands over are beyond the search sphere, so two cheap tests turn them away before the nearest
/// point is computed: the distance from the centre to the triangle's own box and to its plane, each no more than the
/// distance to the triangle. The tests keep a margin far above their rounding, so they turn away only triangles the
/// nearest point would, and the answer is the same.
struct TriangleTest
{
    Vec3 localCentre;
    Real radius;
    Real searchDistance;
    Real keepWithin;   // m from the centre: a triangle nearer is listed in `kept`
    Real rejectBeyond; // the larger of keepWithin and radius + searchDistance, with a margin
    const ObstacleGeometry* geometry;
    /// Of the triangles within the search distance of the sphere's surface: the nearest (triangle -1 before the
    /// first), and the others the centre lies over (see closestFeatures), the only ones that can give a plane.
    NearTriangle* nearest;
    std::vector<NearTriangle>* overFace;
    NearbyTriangles* kept; // or null; count set to -1 once more than its capacity are near

    /// Whether the centre lies over the triangle's face: the direction from its nearest point is the face's normal.
    bool liesOver(const NearTriangle& entry) const
    {
        const int face = geometry->triangleFace[std::size_t(entry.triangle)];
        return std::abs(geometry->faces[std::size_t(face)].normal.dot(entry.normal)) > 0.99;
    }

    void test(const Vec3& a, const Vec3& b, const Vec3& c, int triangleIndex) const
    {
        const Vec3 outside = (a.cwiseMin(b).cwiseMin(c) - localCentre)
                                 .cwiseMax(localCentre - a.cwiseMax(b).cwiseMax(c))
                                 .cwiseMax(Real(0));
        if (outside.squaredNorm() > rejectBeyond * rejectBeyond ||
            std::abs(geometry->triangleNormals[std::size_t(triangleIndex)].dot(localCentre - a)) > rejectBeyond)
        {
            return;
        }
        const Vec3 point = closestPointOnTriangle(localCentre, a, b, c);
        const Vec3 offset = localCentre - point;
        const Real gap = offset.norm();
        take(point, gap, offset / gap, triangleIndex);
    }

    /// The rest of test() for a triangle that passed its tests, given its nearest point to the centre, their distance
    /// `gap` and the direction from the point to the centre (`direction`, used only where `gap` is above rounding).
    void take(const Vec3& point, Real gap, const Vec3& direction, int triangleIndex) const
    {
        if (kept != nullptr && gap <= keepWithin)
        {
            kept->add(triangleIndex, gap);
        }
        if (gap - radius > searchDistance)
        {
            return;
        }
        // A centre on the triangle, to the rounding of its nearest point (a sheet laid on a mesh's face), has no offset
        // to point along, or one whose direction is rounding alone: the triangle's own unit normal (outward for a mesh
        // wound outward; zero for a triangle with no area, which gives no plane) stands in, as EPA's answer would.
        const Real onTriangle = Real(1e-9) * radius + Real(1e-12) * localCentre.cwiseAbs().maxCoeff();
        Vec3 localNormal = direction;
        if (!(gap > onTriangle))
        {
            localNormal = geometry->triangleNormals[std::size_t(triangleIndex)];
            if (localNormal == Vec3::Zero())
            {
                return;
            }
        }
        const NearTriangle entry{gap - radius, localNormal, point, triangleIndex};
        if (nearest->triangle < 0 || nearer(entry, *nearest))
        {
            if (nearest->triangle >= 0 && liesOver(*nearest))
            {
                overFace->push_back(*nearest);
            }
            *nearest = entry;
        }
        else if (liesOver(entry))
        {
            overFace->push_back(entry);
        }
    }
};

/// Bullet's triangle walk listing the triangles it hands over, in its order. Their corners are the geometry's
/// triangleCorners, which hold the bits the walk hands over (ObstacleGeometry.h).
struct TriangleCollector : btTriangleCallback
{
    std::vector<std::int32_t>* triangles;
    void processTriangle(btVector3* /*triangle*/, int /*partId*/, int triangleIndex) override
    {
        triangles->push_back(std::int32_t(triangleIndex));
    }
};

/// Runs `test` on the listed triangles of a mesh, in the list's order: eight at a time on the AVX-512 path
/// (NearestOnTrianglesOfEight.h, the same bits), one at a time otherwise.
void testTriangles(const TriangleTest& test, const ObstacleGeometry& geometry, const std::int32_t* triangles,
                   std::size_t count)
{
    const std::vector<std::array<Vec3, 3>>& corners = geometry.triangleCorners;
    std::size_t k = 0;
    if (nearestOnTrianglesOfEightAvailable())
    {
        NearestOnTrianglesOfEight eight;
        for (; k < count; k += 8)
        {
            const int lanes = int(std::min<std::size_t>(8, count - k));
            nearestOnTrianglesOfEight(corners, geometry.triangleNormals, triangles + k, lanes, test.localCentre,
                                      test.rejectBeyond, eight);
            for (int lane = 0; lane < lanes; ++lane)
            {
                const std::int32_t triangle = triangles[k + std::size_t(lane)];
                if ((eight.near >> lane & 1) != 0)
                {
                    test.take(Vec3(eight.nearestX[lane], eight.nearestY[lane], eight.nearestZ[lane]), eight.gap[lane],
                              Vec3(eight.directionX[lane], eight.directionY[lane], eight.directionZ[lane]), triangle);
                }
                else if ((eight.degenerate >> lane & 1) != 0)
                {
                    const std::array<Vec3, 3>& abc = corners[std::size_t(triangle)];
                    test.test(abc[0], abc[1], abc[2], triangle);
                }
            }
        }
    }
    for (; k < count; ++k)
    {
        const std::array<Vec3, 3>& abc = corners[std::size_t(triangles[k])];
        test.test(abc[0], abc[1], abc[2], triangles[k]);
    }
}

/// Sweep result that also remembers which triangle of a mesh was hit.
struct SweepCollector : btCollisionWorld::ClosestConvexResultCallback
{
    int triangle = -1;
    SweepCollector(const btVector3& from, const btVector3& to) : ClosestConvexResultCallback(from, to) {}
    btScalar addSingleResult(btCollisionWorld::LocalConvexResult& result, bool normalInWorldSpace) override
    {
        const btScalar fraction = ClosestConvexResultCallback::addSingleResult(result, normalInWorldSpace);
        if (result.m_hitFraction <= m_closestHitFraction)
        {
            triangle = result.m_localShapeInfo ? result.m_localShapeInfo->m_triangleIndex : -1;
        }
        return fraction;
    }
};
} // namespace

BulletEnvironment::BulletEnvironment()
    : m_configuration(std::make_unique<btDefaultCollisionConfiguration>(smallPools())),
      m_dispatcher(std::make_unique<btCollisionDispatcher>(m_configuration.get())),
      m_broadphase(std::make_unique<btDbvtBroadphase>()),
      m_world(std::make_unique<btCollisionWorld>(m_dispatcher.get(), m_broadphase.get(), m_configuration.get()))
{
}

BulletEnvironment::~BulletEnvironment()
{
    for (auto& obstacle : m_obstacles)
    {
        m_world->removeCollisionObject(obstacle->object.get());
    }
}

int BulletEnvironment::findObstacle(const std::string& name) const
{
    for (std::size_t i = 0; i < m_obstacles.size(); ++i)
    {
        if (m_obstacles[i]->name == name)
        {
            return int(i);
        }
    }
    return -1;
}

int BulletEnvironment::addObstacle(const ObstacleBody& body, bool partOfRoom)
{
    const std::string named = "obstacle '" + body.name + "'";
    if (body.name.empty())
    {
        throw InputError("obstacle: every obstacle needs a name");
    }
    if (findObstacle(body.name) >= 0)
    {
        throw InputError(named + ": the name is already used by another obstacle");
    }
    const std::vector<PoseKey>& keys = body.path.keys;
    for (std::size_t k = 0; k < keys.size(); ++k)
    {
        if (!std::isfinite(keys[k].time) || (k > 0 && !(keys[k].time > keys[k - 1].time)))
        {
            throw InputError(named + ": path key " + std::to_string(k) + " must come strictly after the one before it");
        }
        if (!keys[k].position.allFinite())
        {
            throw InputError(named + ": path key " + std::to_string(k) + " has a non-finite position");
        }
    }
    if (!body.path.rest.position.allFinite())
    {
        throw InputError(named + ": position must be finite");
    }
    auto obstacle = std::make_unique<Obstacle>();
    obstacle->name = body.name;
    obstacle->path = body.path;
    try
    {
        obstacle->geometry = makeObstacleGeometry(body.shape);
    }
    catch (const InputError& e)
    {
        throw InputError(named + ": " + e.what());
    }
    obstacle->partOfRoom = partOfRoom;
    if (!obstacle->geometry.convex)
    {
        obstacle->meshSlot = m_meshObstacles++;
        m_nearby.clear(); // laid out by mesh slot: made anew for the new count at the next detection
    }
    for (const Vec3& v : obstacle->geometry.vertices)
    {
        obstacle->boundingRadius = std::max(obstacle->boundingRadius, v.norm());
    }
    obstacle->pose = poseAt(obstacle->path, m_time);
    obstacle->motion = motionAt(obstacle->path, m_time);

    obstacle->object = std::make_unique<btCollisionObject>();
    obstacle->object->setCollisionShape(obstacle->geometry.shape.get());
    obstacle->object->setWorldTransform(toBullet(obstacle->pose.position, obstacle->pose.orientation));
    obstacle->object->setUserIndex(int(m_obstacles.size()));
    if (obstacle->path.isKinematic())
    {
        obstacle->object->setCollisionFlags(obstacle->object->getCollisionFlags() |
                                            btCollisionObject::CF_KINEMATIC_OBJECT);
    }
    else
    {
        obstacle->object->setCollisionFlags(obstacle->object->getCollisionFlags() |
                                            btCollisionObject::CF_STATIC_OBJECT);
    }
    // Static filter group, masked against other static objects: Bullet's encoding of the paper's game rule.
    m_world->addCollisionObject(obstacle->object.get(), btBroadphaseProxy::StaticFilter,
                                btBroadphaseProxy::AllFilter ^ btBroadphaseProxy::StaticFilter);
    recordBroadphaseBox(*obstacle);
    m_obstacles.push_back(std::move(obstacle));
    ++m_worldVersion;
    return int(m_obstacles.size()) - 1;
}

void BulletEnvironment::recordBroadphaseBox(Obstacle& obstacle)
{
    const btBroadphaseProxy* proxy = obstacle.object->getBroadphaseHandle();
    obstacle.broadphaseMin = toVec3(proxy->m_aabbMin);
    obstacle.broadphaseMax = toVec3(proxy->m_aabbMax);
}

void BulletEnvironment::extendPath(int index, const std::vector<PoseKey>& keys)
{
    Obstacle& obstacle = *m_obstacles[std::size_t(index)];
    for (const PoseKey& key : keys)
    {
        if (!obstacle.path.keys.empty() && !(key.time > obstacle.path.keys.back().time))
        {
            throw InputError("obstacle '" + obstacle.name + "': a move's keys must come after its path's last key");
        }
        obstacle.path.keys.push_back(key);
    }
    ++m_worldVersion;
    setTime(m_time);
}

void BulletEnvironment::steer(int index, Real time, const Vec3& target, Real speed)
{
    Obstacle& obstacle = *m_obstacles[std::size_t(index)];
    const Pose now = poseAt(obstacle.path, time);
    const Real arrival = time + (target - now.position).norm() / speed;
    obstacle.path.keys = {PoseKey{time, now.position, now.orientation}};
    if (arrival > time)
    {
        obstacle.path.keys.push_back(PoseKey{arrival, target, now.orientation});
    }
    ++m_worldVersion;
    setTime(m_time);
}

void BulletEnvironment::setTime(Real time)
{
    m_time = time;
    m_fastestKinematic = 0;
    for (auto& obstacle : m_obstacles)
    {
        if (!obstacle->path.isKinematic())
        {
            continue;
        }
        obstacle->pose = poseAt(obstacle->path, time);
        obstacle->motion = motionAt(obstacle->path, time);
        obstacle->object->setWorldTransform(toBullet(obstacle->pose.position, obstacle->pose.orientation));
        m_world->updateSingleAabb(obstacle->object.get());
        recordBroadphaseBox(*obstacle);
        m_fastestKinematic =
            std::max(m_fastestKinematic,
                     obstacle->motion.linear.norm() + obstacle->motion.angular.norm() * obstacle->boundingRadius);
    }
}

void BulletEnvironment::candidates(const Vec3& lo, const Vec3& hi, std::vector<int>& out) const
{
    out.clear();
    CandidateCollector collector;
    collector.out = &out;
    m_broadphase->aabbTest(toBullet(lo), toBullet(hi), collector);
    std::sort(out.begin(), out.end());
}

void BulletEnvironment::closestFeatures(int index, const Vec3& centre, Real radius, Real searchDistance,
                                        std::vector<Closest>& out, NearbyTriangles* nearby) const
{
    out.clear();
    const Obstacle& obstacle = *m_obstacles[std::size_t(index)];
    const btTransform& transform = obstacle.object->getWorldTransform();
    const Eigen::Quaternion<Real> toLocal = obstacle.pose.orientation.conjugate();
    if (obstacle.geometry.convex)
    {
        // Near a face, its plane gives the nearest point exactly; near an edge or a vertex, the nearest of the front
        // faces' nearest points does (NearestOnFrontFaces.h). Both in closed form, where GJK searched.
        const Vec3 local = toLocal * (centre - obstacle.pose.position);
        const std::optional<FacePlaneDistance> nearFace = facePlaneDistance(obstacle.geometry, local);
        if (nearFace)
        {
            const Real distance = nearFace->distance - radius;
            if (distance <= searchDistance)
            {
                const Vec3 localNormal = obstacle.geometry.faces[std::size_t(nearFace->face)].normal;
                out.push_back({distance, obstacle.pose.orientation * localNormal,
                               obstacle.pose.orientation * nearFace->point + obstacle.pose.position, nearFace->face});
            }
            return;
        }
        const NearestOnFrontFaces nearEdge = nearestOnFrontFaces(obstacle.geometry, local);
        const Real distance = nearEdge.distance - radius;
        if (distance <= searchDistance)
        {
            out.push_back({distance, obstacle.pose.orientation * nearEdge.normal,
                           obstacle.pose.orientation * nearEdge.point + obstacle.pose.position,
                           obstacle.geometry.faceAt(nearEdge.point, nearEdge.normal)});
        }
        return;
    }
    // Mesh: the triangles near the sphere, in the mesh's own frame. Their list is kept per thread (the queries run on
    // the task pool's threads) and reused: a new one for each mass's query would be a heap allocation or more per mass
    // and frame. A mass whose triangles were kept (NearbyTriangles.h) and which has not left their sphere tests those
    // alone; otherwise Bullet walks the mesh's tree for the triangles whose boxes meet the search box, grown by the
    // kept sphere's margin when they are to be kept.
    thread_local std::vector<NearTriangle> overFace;
    overFace.clear();
    NearTriangle nearest{0, Vec3::Zero(), Vec3::Zero(), -1};
    const Vec3 local = toLocal * (centre - obstacle.pose.position);
    const Real reach = radius + std::max(searchDistance, Real(0));
    TriangleTest test;
    test.localCentre = local;
    test.radius = radius;
    test.searchDistance = searchDistance;
    test.geometry = &obstacle.geometry;
    test.nearest = &nearest;
    test.overFace = &overFace;
    test.kept = nullptr;
    test.keepWithin = 0;
    if (nearby != nullptr && nearby->covers(local, reach))
    {
        test.rejectBeyond = reach + Real(1e-9) * reach + Real(1e-12);
        const Real moved = (local - nearby->centre).norm();
        // The kept triangles before the first that is too far to be near (they are in increasing distance).
        std::array<std::int32_t, NearbyTriangles::capacity> triangles; // the first `near` are written below
        std::size_t near = 0;
        for (; near < std::size_t(nearby->count); ++near)
        {
            const NearbyTriangles::Entry& entry = nearby->entry[near];
            if (Real(entry.distance) - moved > test.rejectBeyond)
            {
                break;
            }
            triangles[near] = entry.triangle;
        }
        testTriangles(test, obstacle.geometry, triangles.data(), near);
    }
    else
    {
        Real extent = reach;
        if (nearby != nullptr)
        {
            extent = reach + NearbyTriangles::margin * radius;
            nearby->centre = local;
            nearby->radius = extent;
            nearby->count = 0;
            test.kept = nearby;
            test.keepWithin = extent;
        }
        test.rejectBeyond = extent + Real(1e-9) * extent + Real(1e-12);
        thread_local std::vector<std::int32_t> walked;
        walked.clear();
        TriangleCollector collector;
        collector.triangles = &walked;
        const auto& mesh = static_cast<const btBvhTriangleMeshShape&>(*obstacle.geometry.shape);
        const_cast<btBvhTriangleMeshShape&>(mesh).processAllTriangles(
            &collector, toBullet(local - Vec3::Constant(extent)), toBullet(local + Vec3::Constant(extent)));
        testTriangles(test, obstacle.geometry, walked.data(), walked.size());
        if (nearby != nullptr)
        {
            nearby->sort();
        }
    }
    // The nearest triangle's plane, and up to two more from triangles the centre lies over (a crease of a concave
    // mould, where one plane would let the sphere sink into the other face): there the closest point is inside the
    // triangle, so the contact normal is its face's. A farther triangle whose nearest point is on its rim gives no
    // plane: at a convex edge its plane, tangent at the edge and fixed for the frame, lies above the nearer face away
    // from the edge, so a mass sliding down that face would be thrown off it each substep (a glassy 40x2x40 PET sheet
    // on the pyramid mesh would gain 154 J in one step that way). So the test keeps only the nearest and the triangles
    // the centre lies over, which are put in order (nearest first, ties by triangle): listing and sorting every
    // triangle in the search box would take a tenth of a vacuum-forming run. All in the mesh's frame; the planes kept
    // are turned into the world.
    if (nearest.triangle < 0)
    {
        return;
    }
    std::sort(overFace.begin(), overFace.end(), nearer);
    for (std::size_t k = 0; k <= overFace.size() && out.size() < 3; ++k)
    {
        const NearTriangle* entry = k == 0 ? &nearest : &overFace[k - 1];
        const Vec3 normal = toVec3(transform.getBasis() * toBullet(entry->normal));
        bool distinct = true;
        for (const Closest& kept : out)
        {
            distinct = distinct && kept.normal.dot(normal) < 0.99;
        }
        if (distinct)
        {
            out.push_back({entry->distance, normal, toVec3(transform(toBullet(entry->point))),
                           obstacle.geometry.triangleFace[std::size_t(entry->triangle)]});
        }
    }
}

void BulletEnvironment::findContacts(const std::vector<Vec3>& x, const std::vector<Real>& reach, Real radius, Real dt,
                                     ContactPlaneLists& out)
{
    // The surface's mean velocity over the frame, so a path that starts or stops within it is followed.
    m_frameMotion.assign(m_obstacles.size(), Motion{});
    for (std::size_t index = 0; index < m_obstacles.size(); ++index)
    {
        const KinematicPath& path = m_obstacles[index]->path;
        if (path.isKinematic() && dt > 0)
        {
            m_frameMotion[index] = averageMotion(path, m_time, m_time + dt);
        }
    }
    // Bullet's queries used here only read the world (the broadphase's box test, a mesh's triangle walk), so chunks of
    // masses run on all threads, each into its own list. Joined in chunk order (ContactPlanes::index joins them), the
    // planes come out in mass order whatever the thread count.
    const std::size_t chunks = chunkCount(x.size(), detectionChunkSize);
    out.resize(chunks);
    // Each mass's kept triangles of each mesh obstacle; a sheet of another size starts with none kept.
    if (m_nearby.size() != x.size() * std::size_t(m_meshObstacles))
    {
        m_nearby.assign(x.size() * std::size_t(m_meshObstacles), NearbyTriangles{});
    }
    m_chunkEights.reserveChunks(chunks);
    // A moving obstacle's planes move with it: the still masses' planes are reused only among still obstacles.
    const bool stillWorld = std::none_of(m_obstacles.begin(), m_obstacles.end(),
                                         [](const auto& obstacle) { return obstacle->path.isKinematic(); });
    const bool reuse =
        stillWorld && m_still.radius == radius && m_still.world == m_worldVersion && m_still.x.size() == x.size();
    m_still.x.resize(x.size());
    m_still.reach.resize(x.size());
    m_still.firstPlane.resize(x.size());
    m_still.endPlane.resize(x.size());
    m_still.planes.reserveChunks(chunks);
    parallelFor(x.size(), detectionChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    const std::size_t chunk = begin / detectionChunkSize;
                    ChunkQuery query{
                        x, reach, radius, dt, m_fastestKinematic * dt, m_chunkEights[chunk], m_nearby.data()};
                    query.stillReused = reuse;
                    findChunkContacts(query, begin, end, out[chunk]);
                    m_still.planes[chunk] = out[chunk];
                });
    m_still.radius = stillWorld ? radius : Real(-1);
    m_still.world = m_worldVersion;
}

bool BulletEnvironment::stillSince(const ChunkQuery& query, std::size_t i) const
{
    return query.stillReused && query.x[i] == m_still.x[i] && query.reach[i] == m_still.reach[i];
}

void BulletEnvironment::findChunkContacts(ChunkQuery& query, std::size_t begin, std::size_t end,
                                          std::vector<ContactPlane>& planes)
{
    planes.clear();
    const std::vector<ContactPlane>& stillPlanes = m_still.planes[begin / detectionChunkSize];
    // A mass still since the last detection copies its planes from it (m_still); the others ask the obstacles. Each
    // mass's planes are listed in mass order either way.
    const auto takeStillPlanes = [&](std::size_t i)
    {
        const std::uint32_t first = std::uint32_t(planes.size());
        planes.insert(planes.end(), stillPlanes.begin() + std::ptrdiff_t(m_still.firstPlane[i]),
                      stillPlanes.begin() + std::ptrdiff_t(m_still.endPlane[i]));
        m_still.firstPlane[i] = first;
        m_still.endPlane[i] = std::uint32_t(planes.size());
    };
    bool allStill = true;
    for (std::size_t i = begin; i < end && allStill; ++i)
    {
        allStill = stillSince(query, i);
    }
    if (allStill)
    {
        for (std::size_t i = begin; i < end; ++i)
        {
            takeStillPlanes(i);
        }
        return;
    }
    // One broadphase query for the chunk's whole reach box; each mass then tests the few obstacles it found against its
    // own box. An obstacle left out there cannot give a plane: a plane needs the mass within its search distance of
    // the surface, hence its box to meet the obstacle's.
    Vec3 lo = Vec3::Constant(std::numeric_limits<Real>::infinity());
    Vec3 hi = -lo;
    for (std::size_t i = begin; i < end; ++i)
    {
        const Vec3 extent = Vec3::Constant(query.reach[i] + query.obstacleTravel + query.radius);
        lo = lo.cwiseMin(query.x[i] - extent);
        hi = hi.cwiseMax(query.x[i] + extent);
    }
    candidates(lo, hi, query.near);
    // On the AVX-512 path, eight masses at a time get their face planes of each convex obstacle near the chunk in one
    // pass (FacePlanesOfEight.h); a mass whose nearest point is on an edge, and every other case, takes the scalar
    // query. Planes are listed mass by mass either way.
    query.eights.resize(query.near.size());
    const bool byEights = facePlanesOfEightAvailable();
    for (std::size_t first = begin; first < end; first += 8)
    {
        const std::size_t last = std::min(first + 8, end);
        query.first = first;
        query.batched = 0;
        std::uint8_t still = 0;
        for (std::size_t i = first; i < last; ++i)
        {
            still |= std::uint8_t(stillSince(query, i) ? 1u << (i - first) : 0u);
        }
        // The eight's box (each mass's own, as appendMassPlanes tests): an obstacle it does not meet gives none of the
        // eight a plane, so its pass is skipped (in a chunk spanning two obstacles, half the passes would be wasted).
        Vec3 eightLo = Vec3::Constant(std::numeric_limits<Real>::infinity());
        Vec3 eightHi = -eightLo;
        for (std::size_t i = first; byEights && i < last; ++i)
        {
            const Vec3 extent = Vec3::Constant(query.reach[i] + query.obstacleTravel + query.radius);
            eightLo = eightLo.cwiseMin(query.x[i] - extent);
            eightHi = eightHi.cwiseMax(query.x[i] + extent);
        }
        const bool eightStill = still == 0xFF;
        for (std::size_t slot = 0; byEights && !eightStill && last == first + 8 && slot < query.near.size() && slot < 8;
             ++slot)
        {
            const Obstacle& obstacle = *m_obstacles[std::size_t(query.near[slot])];
            const bool meets = !((eightLo.array() > obstacle.broadphaseMax.array()).any() ||
                                 (eightHi.array() < obstacle.broadphaseMin.array()).any());
            if (meets && obstacle.geometry.convex && !obstacle.geometry.faces.empty())
            {
                facePlanesOfEight(obstacle.geometry, obstacle.pose, &query.x[first], query.eights[slot]);
                query.batched |= std::uint8_t(1u << slot);
            }
        }
        for (std::size_t i = first; i < last; ++i)
        {
            if ((still >> (i - first) & 1u) != 0)
            {
                takeStillPlanes(i);
                continue;
            }
            m_still.firstPlane[i] = std::uint32_t(planes.size());
            appendMassPlanes(query, i, planes);
            m_still.endPlane[i] = std::uint32_t(planes.size());
            m_still.x[i] = query.x[i];
            m_still.reach[i] = query.reach[i];
        }
    }
}

void BulletEnvironment::appendMassPlanes(ChunkQuery& query, std::size_t i, std::vector<ContactPlane>& planes) const
{
    const Real searchDistance = query.reach[i] + query.obstacleTravel;
    const Vec3 extent = Vec3::Constant(searchDistance + query.radius);
    const Vec3 massLo = query.x[i] - extent;
    const Vec3 massHi = query.x[i] + extent;
    const std::size_t lane = i - query.first;
    for (std::size_t slot = 0; slot < query.near.size(); ++slot)
    {
        const int index = query.near[slot];
        const Obstacle& obstacle = *m_obstacles[std::size_t(index)];
        if ((massLo.array() > obstacle.broadphaseMax.array()).any() ||
            (massHi.array() < obstacle.broadphaseMin.array()).any())
        {
            continue;
        }
        // A still surface's velocity, motion.at with zero motion, is +0 in every coordinate for any finite point: the
        // default plane's. Left so, it is not computed; computed, the cross product's result goes through memory and
        // stalls the loop (perf annotate).
        const bool moving = obstacle.path.isKinematic() && query.dt > 0;
        const Motion& motion = m_frameMotion[std::size_t(index)];
        if ((query.batched >> slot & 1u) != 0 && (query.eights[slot].found >> lane & 1u) != 0)
        {
            // closestFeatures' face-plane case, computed for the eight.
            const FacePlanesOfEight& e = query.eights[slot];
            if (e.distance[lane] - query.radius <= searchDistance)
            {
                // Written in place, coordinate by coordinate: a plane built aside and copied in would be read back as
                // pairs of its coordinates just stored one by one, a stall on every plane (perf annotate).
                ContactPlane& plane = planes.emplace_back();
                plane.mass = Index(i);
                plane.obstacle = index;
                plane.face = int(e.face[lane]);
                plane.normal.x() = e.normalX[lane];
                plane.normal.y() = e.normalY[lane];
                plane.normal.z() = e.normalZ[lane];
                plane.offset = e.offset[lane];
                if (moving)
                {
                    plane.velocity =
                        motion.at(Vec3(e.pointX[lane], e.pointY[lane], e.pointZ[lane]), obstacle.pose.position);
                }
            }
            continue;
        }
        NearbyTriangles* nearby = obstacle.meshSlot >= 0
                                      ? query.nearby + i * std::size_t(m_meshObstacles) + std::size_t(obstacle.meshSlot)
                                      : nullptr;
        closestFeatures(index, query.x[i], query.radius, searchDistance, query.features, nearby);
        for (const Closest& feature : query.features)
        {
            ContactPlane plane;
            plane.mass = Index(i);
            plane.obstacle = index;
            plane.face = feature.face;
            plane.normal = feature.normal;
            plane.offset = feature.normal.dot(feature.point);
            if (moving)
            {
                plane.velocity = motion.at(feature.point, obstacle.pose.position);
            }
            planes.push_back(plane);
        }
    }
}

std::optional<SweepHit> BulletEnvironment::sweep(const Vec3& from, const Vec3& to, Real radius)
{
    if ((to - from).squaredNorm() == 0)
    {
        return std::nullopt;
    }
    btSphereShape sphere(radius);
    btTransform start;
    start.setIdentity();
    start.setOrigin(toBullet(from));
    btTransform end;
    end.setIdentity();
    end.setOrigin(toBullet(to));
    SweepCollector collector(start.getOrigin(), end.getOrigin());
    m_world->convexSweepTest(&sphere, start, end, collector);
    if (!collector.hasHit())
    {
        return std::nullopt;
    }
    SweepHit hit;
    hit.fraction = collector.m_closestHitFraction;
    hit.normal = toVec3(collector.m_hitNormalWorld).normalized();
    hit.obstacle = collector.m_hitCollisionObject->getUserIndex();
    const Obstacle& obstacle = *m_obstacles[std::size_t(hit.obstacle)];
    if (obstacle.geometry.convex)
    {
        const Eigen::Quaternion<Real> toLocal = obstacle.pose.orientation.conjugate();
        hit.face = obstacle.geometry.faceAt(toLocal * (toVec3(collector.m_hitPointWorld) - obstacle.pose.position),
                                            toLocal * hit.normal);
    }
    else if (collector.triangle >= 0 && std::size_t(collector.triangle) < obstacle.geometry.triangleFace.size())
    {
        hit.face = obstacle.geometry.triangleFace[std::size_t(collector.triangle)];
    }
    return hit;
}

Vec3 BulletEnvironment::pointVelocity(int index, const Vec3& point, Real dt)
{
    if (index < 0 || index >= obstacleCount() || !(dt > 0))
    {
        return Vec3::Zero();
    }
    const Obstacle& obstacle = *m_obstacles[std::size_t(index)];
    if (!obstacle.path.isKinematic())
    {
        return Vec3::Zero();
    }
    return averageMotion(obstacle.path, m_time, m_time + dt).at(point, obstacle.pose.position);
}

SurfaceDistance BulletEnvironment::nearestSurface(const Vec3& x, Real maxDistance)
{
    SurfaceDistance nearest;
    nearest.distance = maxDistance;
    std::vector<int> near;
    std::vector<Closest> features;
    candidates(x - Vec3::Constant(maxDistance), x + Vec3::Constant(maxDistance), near);
    for (int index : near)
    {
        closestFeatures(index, x, probeRadius, maxDistance, features);
        for (const Closest& feature : features)
        {
            const Real distance = feature.distance + probeRadius;
            if (distance < nearest.distance)
            {
                nearest = {distance, index, feature.face};
            }
        }
    }
    return nearest;
}
} // namespace masse::bridge
