// Obstacle shapes in Bullet: faces, distances against closed forms, and refusal of bad geometry.

#include "support/JoinedPlanes.h"
#include "support/TestSystems.h"

#include "bridge/BulletEnvironment.h"
#include "bridge/FacePlaneDistance.h"
#include "bridge/FacePlanesOfEight.h"
#include "bridge/NearestOnFrontFaces.h"
#include "bridge/StlFile.h"
#include "scene/Room.h"
#include "scene/shapes/BoxShape.h"
#include "scene/shapes/PrismShape.h"

#include "core/InputError.h"
#include "core/contact/ClosestPointOnTriangle.h"
#include "core/forces/SimdPath.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>

using namespace masse;
using namespace masse::bridge;

namespace
{
ObstacleBody box(const std::string& name, const Vec3& position, const Vec3& half)
{
    ObstacleBody body;
    body.name = name;
    body.shape = scene::boxSolid(half);
    body.path.rest.position = position;
    return body;
}

ObstacleBody prism(const std::string& name, Real width, Real height, Real length, Real apex = 0)
{
    ObstacleBody body;
    body.name = name;
    body.shape = scene::prismSolid({width, height, length, apex});
    return body;
}

/// Exact signed distance from a point to an axis-aligned box (negative inside).
Real boxDistance(const Vec3& p, const Vec3& centre, const Vec3& half)
{
    const Vec3 q = (p - centre).cwiseAbs() - half;
    const Real outside = q.cwiseMax(0.0).norm();
    const Real inside = std::min(q.maxCoeff(), 0.0);
    return outside + inside;
}

/// The grid points (step.x i, step.y j, step.z k) for |i| <= nx, |j| <= ny, |k| <= nz.
std::vector<Vec3> gridPoints(const Vec3& step, int nx, int ny, int nz)
{
    std::vector<Vec3> points;
    for (int i = -nx; i <= nx; ++i)
    {
        for (int j = -ny; j <= ny; ++j)
        {
            for (int k = -nz; k <= nz; ++k)
            {
                points.emplace_back(step.x() * i, step.y() * j, step.z() * k);
            }
        }
    }
    return points;
}

std::string errorOf(const ObstacleBody& body)
{
    return masse::test::inputErrorOf(
        [&]
        {
            BulletEnvironment environment;
            environment.addObstacle(body);
        });
}
} // namespace

TEST(ObstacleGeometry, BoxFacesFollowTheDocumentedOrder)
{
    const ObstacleGeometry g = makeObstacleGeometry(box("b", Vec3::Zero(), Vec3(1, 2, 3)).shape);
    ASSERT_EQ(g.faces.size(), 6u);
    const Vec3 normals[6] = {Vec3::UnitX(),  -Vec3::UnitX(), Vec3::UnitY(),
                             -Vec3::UnitY(), Vec3::UnitZ(),  -Vec3::UnitZ()};
    const Real offsets[6] = {1, 1, 2, 2, 3, 3};
    for (int f = 0; f < 6; ++f)
    {
        EXPECT_NEAR((g.faces[std::size_t(f)].normal - normals[f]).norm(), 0.0, 1e-12) << f;
        EXPECT_NEAR(g.faces[std::size_t(f)].offset, offsets[f], 1e-12) << f;
    }
    EXPECT_EQ(g.faceAt(Vec3(0.2, 2.0, -1.0), Vec3::UnitY()), 2);
    EXPECT_EQ(g.faceAt(Vec3(1.0, 0.5, 0.5), Vec3::UnitX()), 0);
}

TEST(ObstacleGeometry, HullOfCubeCornersHasSixFacesAndPrismFive)
{
    ObstacleShape hull;
    hull.kind = SolidKind::Hull;
    for (int k = 0; k < 8; ++k)
    {
        hull.hullPoints.emplace_back(k & 1 ? 1 : -1, k & 2 ? 1 : -1, k & 4 ? 1 : -1);
    }
    hull.hullPoints.emplace_back(0.1, 0.2, 0.3); // an interior point is not a vertex
    const ObstacleGeometry cube = makeObstacleGeometry(hull);
    EXPECT_EQ(cube.vertices.size(), 8u);
    EXPECT_EQ(cube.faces.size(), 6u);

    const ObstacleGeometry wedge = makeObstacleGeometry(prism("prism", 2, 1, 3).shape);
    ASSERT_EQ(wedge.faces.size(), 5u);
    EXPECT_NEAR((wedge.faces[0].normal + Vec3::UnitY()).norm(), 0.0, 1e-12);
    EXPECT_GT(wedge.faces[1].normal.x(), 0.0);
    EXPECT_LT(wedge.faces[2].normal.x(), 0.0);
    EXPECT_NEAR((wedge.faces[3].normal - Vec3::UnitZ()).norm(), 0.0, 1e-12);
}

// Bullet's narrowphase against the closed-form distance to a box: outside a face, an edge and a corner, and inside.
TEST(ObstacleGeometry, NearestSurfaceMatchesBoxDistance)
{
    BulletEnvironment environment;
    const Vec3 centre(0.3, -1.0, 0.2);
    const Vec3 half(0.5, 0.25, 0.75);
    const int index = environment.addObstacle(box("box", centre, half));
    const Vec3 points[] = {centre + Vec3(0.1, 0.4, 0.2), centre + Vec3(0.7, 0.4, 0.0),  centre + Vec3(0.6, 0.3, 0.9),
                           centre + Vec3(0.1, 0.2, 0.3), centre + Vec3(0.45, 0.0, 0.0), centre + Vec3(0.0, 0.25, 0.0)};
    for (const Vec3& p : points)
    {
        const SurfaceDistance d = environment.nearestSurface(p, 2.0);
        EXPECT_EQ(d.obstacle, index);
        EXPECT_NEAR(d.distance, boxDistance(p, centre, half), 1e-6) << p.transpose();
    }
    EXPECT_EQ(environment.nearestSurface(centre + Vec3(3, 0, 0), 1.0).obstacle, -1);
    EXPECT_EQ(environment.nearestSurface(centre + Vec3(0.1, 0.4, 0.2), 1.0).face, 2); // above the top face
}

TEST(ObstacleGeometry, MeshFromObjKeepsItsFaces)
{
    ObstacleBody pyramid;
    pyramid.name = "pyramid";
    pyramid.shape.kind = SolidKind::Mesh;
    pyramid.shape.polygons = loadMeshFile(std::string(MASSE_SOURCE_DIR) + "/data/meshes/pyramid.obj", "pyramid");
    BulletEnvironment environment;
    const int index = environment.addObstacle(pyramid);
    const ObstacleGeometry& g = environment.obstacle(index).geometry;
    EXPECT_FALSE(g.convex);
    EXPECT_EQ(g.faces.size(), 5u);
    EXPECT_EQ(g.triangleFace.size(), 6u); // the square base is two triangles
    // Just above the apex the nearest face is a side; just below the base's middle it is the base (face 0).
    const SurfaceDistance below = environment.nearestSurface(Vec3(0.1, -0.05, 0.1), 0.5);
    EXPECT_EQ(below.face, 0);
    EXPECT_NEAR(below.distance, 0.05, 1e-6);
}

TEST(ObstacleGeometry, BadObstaclesAreRefusedByName)
{
    ObstacleBody flat;
    flat.name = "flat";
    flat.shape.kind = SolidKind::Hull;
    flat.shape.hullPoints = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 0, 1), Vec3(1, 0, 1)};
    EXPECT_NE(errorOf(flat).find("obstacle 'flat': a hull needs at least 4 points not all in one plane"),
              std::string::npos)
        << errorOf(flat);
    flat.shape.hullPoints.resize(3);
    EXPECT_NE(errorOf(flat).find("got 3 points"), std::string::npos);

    // Mesh files are read by name of the obstacle they are for.
    auto loadError = [](const std::string& path, const std::string& owner)
    { return masse::test::inputErrorOf([&] { loadMeshFile(path, owner); }); };
    EXPECT_NE(
        loadError("/no/such/file.obj", "ghost").find("obstacle 'ghost': mesh file '/no/such/file.obj' does not exist"),
        std::string::npos);
    const std::string broken = loadError(std::string(MASSE_SOURCE_DIR) + "/data/meshes/broken.obj", "broken");
    EXPECT_NE(broken.find("obstacle 'broken'"), std::string::npos) << broken;

    EXPECT_EQ(masse::test::inputErrorOf([] { scene::boxSolid(Vec3(1, 0, 1)); }),
              "halfExtents.y: must be a positive number of metres (got 0)");
    ObstacleBody faceless;
    faceless.name = "faceless";
    faceless.shape.kind = SolidKind::Mesh;
    faceless.shape.polygons.vertices = {Vec3::Zero(), Vec3::UnitX(), Vec3::UnitZ()};
    EXPECT_EQ(errorOf(faceless), "obstacle 'faceless': mesh: has no faces");
    faceless.shape.polygons.faces = {{0, 1, 3}};
    EXPECT_EQ(errorOf(faceless), "obstacle 'faceless': mesh: a face names vertex 3 of 3");

    BulletEnvironment environment;
    environment.addObstacle(box("twin", Vec3::Zero(), Vec3(1, 1, 1)));
    EXPECT_THROW(environment.addObstacle(box("twin", Vec3(5, 0, 0), Vec3(1, 1, 1))), InputError);

    ContactSettings contact;
    contact.radius = 0;
    EXPECT_THROW(validate(contact), InputError);
}

TEST(ObstacleGeometry, RoomHasTablesFloorAndWalls)
{
    BulletEnvironment environment;
    scene::addRoom(environment, scene::RoomSpec{});
    EXPECT_EQ(environment.obstacleCount(), 6);
    const int floor = environment.findObstacle("floor");
    ASSERT_GE(floor, 0);
    const SurfaceDistance d = environment.nearestSurface(Vec3(0, -2.5, 0), 1.0);
    EXPECT_EQ(d.obstacle, floor);
    EXPECT_NEAR(d.distance, 0.31, 1e-9); // floor at y = -2.81 (Table 1)
    EXPECT_NEAR(environment.nearestSurface(Vec3(6.0, 0, 0), 1.0).distance, 0.5, 1e-9);
}

// The face-plane shortcut (FacePlaneDistance.h) against the closed-form distance to a box, over a grid of points
// inside and around it: where it answers, the distance is exact to rounding (1e-12 m); it answers inside and in front
// of each face, and leaves the edge and corner regions (to nearestOnFrontFaces).
TEST(ObstacleGeometry, FacePlaneDistanceIsExactWhereItAnswers)
{
    const Vec3 half(0.5, 0.25, 0.75);
    const ObstacleGeometry g = makeObstacleGeometry(box("box", Vec3::Zero(), half).shape);
    int answered = 0;
    int left = 0;
    for (const Vec3& p : gridPoints(Vec3(0.13, 0.07, 0.19), 6, 6, 6))
    {
        const Vec3 q = p.cwiseAbs() - half;
        const bool edgeOrCorner = (q.array() > 0).count() >= 2;
        const std::optional<FacePlaneDistance> d = facePlaneDistance(g, p);
        if (!d)
        {
            EXPECT_TRUE(edgeOrCorner) << p.transpose();
            ++left;
            continue;
        }
        ++answered;
        EXPECT_FALSE(edgeOrCorner) << p.transpose();
        EXPECT_NEAR(d->distance, boxDistance(p, Vec3::Zero(), half), 1e-12) << p.transpose();
        EXPECT_NEAR((d->point - p).norm(), std::abs(d->distance), 1e-12) << p.transpose();
        EXPECT_NEAR(boxDistance(d->point, Vec3::Zero(), half), 0.0, 1e-12) << p.transpose();
    }
    EXPECT_GT(answered, 0);
    EXPECT_GT(left, 0);
}

// On a prism (slanted faces), the answered point lies on the solid's surface and within every face's half-space, so
// it is the nearest point (no point of the solid lies in front of the answered face's plane); it is as far as stated.
TEST(ObstacleGeometry, FacePlaneDistanceOnAPrismLiesOnItsSurface)
{
    const ObstacleGeometry g = makeObstacleGeometry(prism("wedge", 1.0, 1.6, 1.6, 0.5).shape);
    int answered = 0;
    for (const Vec3& p : gridPoints(Vec3(0.11, 0.13, 0.31), 8, 8, 3))
    {
        const std::optional<FacePlaneDistance> d = facePlaneDistance(g, p);
        if (!d)
        {
            continue;
        }
        ++answered;
        const Face& face = g.faces[std::size_t(d->face)];
        EXPECT_NEAR(face.normal.dot(d->point) - face.offset, 0.0, 1e-12) << p.transpose();
        for (const Face& other : g.faces)
        {
            EXPECT_LE(other.normal.dot(d->point) - other.offset, 1e-12) << p.transpose();
        }
        EXPECT_NEAR((p - d->point).norm(), std::abs(d->distance), 1e-12) << p.transpose();
        EXPECT_NEAR(face.normal.dot(p) - face.offset, d->distance, 1e-12) << p.transpose();
    }
    EXPECT_GT(answered, 100);
}

// What the face-plane shortcut leaves (edges and corners of a box) against the closed-form distance to a box, over
// the same grid: the distance is exact to rounding (1e-12 m), the point lies on the box, and the normal points from it
// to the point asked about.
TEST(ObstacleGeometry, NearestOnFrontFacesMatchesBoxDistanceAtEdgesAndCorners)
{
    const Vec3 half(0.5, 0.25, 0.75);
    const ObstacleGeometry g = makeObstacleGeometry(box("box", Vec3::Zero(), half).shape);
    int edgesAndCorners = 0;
    for (const Vec3& p : gridPoints(Vec3(0.13, 0.07, 0.19), 6, 6, 6))
    {
        if (facePlaneDistance(g, p))
        {
            continue;
        }
        ++edgesAndCorners;
        const NearestOnFrontFaces d = nearestOnFrontFaces(g, p);
        EXPECT_NEAR(d.distance, boxDistance(p, Vec3::Zero(), half), 1e-12) << p.transpose();
        EXPECT_NEAR(boxDistance(d.point, Vec3::Zero(), half), 0.0, 1e-12) << p.transpose();
        EXPECT_NEAR((p - (d.point + d.distance * d.normal)).norm(), 0.0, 1e-12) << p.transpose();
    }
    EXPECT_GT(edgesAndCorners, 100);
}

// On a prism with a slanted apex (faces at other angles than a box's), every point outside: the answer is the nearest
// point of the solid by its certificate. It lies on the solid (behind every face plane, on one of them) and no vertex
// v lies in front of the plane through it normal to p - q, (p - q) . (v - q) <= 0; a convex solid is the hull of its
// vertices, so no point of it is nearer to p. Tolerances 1e-12 (metres, or metres squared for the products).
TEST(ObstacleGeometry, NearestOnFrontFacesOnAPrismIsTheNearestPoint)
{
    const ObstacleGeometry g = makeObstacleGeometry(prism("wedge", 1.0, 1.6, 1.6, 0.5).shape);
    int outside = 0;
    int edgesAndCorners = 0;
    for (const Vec3& p : gridPoints(Vec3(0.11, 0.13, 0.23), 8, 8, 4))
    {
        Real height = -std::numeric_limits<Real>::infinity();
        for (const Face& face : g.faces)
        {
            height = std::max(height, face.normal.dot(p) - face.offset);
        }
        if (!(height > 0))
        {
            continue;
        }
        ++outside;
        edgesAndCorners += facePlaneDistance(g, p) ? 0 : 1;
        const NearestOnFrontFaces d = nearestOnFrontFaces(g, p);
        Real onSurface = -std::numeric_limits<Real>::infinity();
        for (const Face& face : g.faces)
        {
            const Real q = face.normal.dot(d.point) - face.offset;
            EXPECT_LE(q, 1e-12) << p.transpose();
            onSurface = std::max(onSurface, q);
        }
        EXPECT_NEAR(onSurface, 0.0, 1e-12) << p.transpose();
        for (const Vec3& v : g.vertices)
        {
            EXPECT_LE((p - d.point).dot(v - d.point), 1e-12) << p.transpose();
        }
        EXPECT_NEAR((p - d.point).norm(), d.distance, 1e-12) << p.transpose();
        EXPECT_NEAR(d.normal.norm(), 1.0, 1e-12) << p.transpose();
        // Where the face plane answers too, both give the same distance.
        if (const std::optional<FacePlaneDistance> face = facePlaneDistance(g, p))
        {
            EXPECT_NEAR(face->distance, d.distance, 1e-12) << p.transpose();
        }
    }
    EXPECT_GT(outside, 500);
    EXPECT_GT(edgesAndCorners, 100);
}

// Points on the surface (the vertices and the edges' midpoints of slanted solids), some of them in front of a face's
// plane by a rounding error only: the answer is a finite unit normal and a distance of at most 1e-12 m, never the 0/0
// of a direction from a point to itself.
TEST(ObstacleGeometry, NearestOnFrontFacesOfAPointOnTheSurfaceHasAFiniteNormal)
{
    int inFront = 0;
    for (const Real apex : {0.0, 0.5, 0.37, -0.29})
    {
        const ObstacleGeometry g = makeObstacleGeometry(prism("wedge", 1.1, 1.3, 0.7, apex).shape);
        std::vector<Vec3> points = g.vertices;
        for (const Face& face : g.faces)
        {
            for (std::size_t k = 0; k < face.vertices.size(); ++k)
            {
                const Vec3& a = g.vertices[std::size_t(face.vertices[k])];
                const Vec3& b = g.vertices[std::size_t(face.vertices[(k + 1) % face.vertices.size()])];
                points.push_back((a + b) / 3 + (a + b) / 6);
            }
        }
        for (const Vec3& p : points)
        {
            bool front = false;
            for (const Face& face : g.faces)
            {
                front = front || face.normal.dot(p) - face.offset > 0;
            }
            if (!front || facePlaneDistance(g, p))
            {
                continue;
            }
            ++inFront;
            const NearestOnFrontFaces d = nearestOnFrontFaces(g, p);
            EXPECT_TRUE(d.normal.allFinite()) << p.transpose();
            EXPECT_NEAR(d.normal.norm(), 1.0, 1e-12) << p.transpose();
            EXPECT_LE(d.distance, 1e-12) << p.transpose();
        }
    }
    std::cout << inFront << " surface points in front of a plane by rounding\n";
}

namespace
{
/// A mesh obstacle of two rectangles 2 m long (along z) meeting along z at x = 0, y = `creaseHeight`, each falling
/// (or rising) to y = 0 at x = -1 and x = +1: a roof (a convex ridge) for a positive height, a valley (a concave
/// crease) for a negative one.
ObstacleBody twoSlopes(const std::string& name, Real creaseHeight)
{
    const std::string path = ::testing::TempDir() + name + ".obj";
    std::ofstream obj(path);
    obj << "v -1 0 -1\nv 0 " << creaseHeight << " -1\nv 1 0 -1\nv -1 0 1\nv 0 " << creaseHeight << " 1\nv 1 0 1\n"
        << "f 1 5 2\nf 1 4 5\nf 2 6 3\nf 2 5 6\n";
    obj.close();
    ObstacleBody body;
    body.name = name;
    body.shape.kind = SolidKind::Mesh;
    body.shape.polygons = loadMeshFile(path, name);
    return body;
}

/// The planes the detector gives one mass at `x` (radius 10 mm, at rest, dt 0.03 s).
std::vector<ContactPlane> planesAt(BulletEnvironment& environment, const Vec3& x)
{
    const Real radius = 0.01;
    ContactPlaneLists lists;
    environment.findContacts({x}, {0.05}, radius, 0.03, lists);
    return test::joinedPlanes(lists);
}
} // namespace

// Beside a convex ridge of a mesh a mass gets the plane of the face it lies over and none from the face beyond the
// ridge: that face's nearest point is on the ridge, and a plane tangent there, fixed for the frame, lies above the
// nearer face away from the ridge (a sheet sliding down the face would be thrown off it each substep). In a concave
// crease a mass over both faces gets both planes, or it would sink into the second.
TEST(ObstacleGeometry, MeshGivesASecondPlaneInACreaseButNotBesideARidge)
{
    BulletEnvironment roof;
    roof.addObstacle(twoSlopes("roof", 0.5));
    const Vec3 rightNormal = Vec3(0.5, 1, 0).normalized();
    const Vec3 nearRidge = Vec3(0.01, 0.495, 0.0) + 0.015 * rightNormal; // 15 mm above the right face, by the ridge
    const std::vector<ContactPlane> ridgePlanes = planesAt(roof, nearRidge);
    ASSERT_EQ(ridgePlanes.size(), 1u);
    EXPECT_NEAR(ridgePlanes[0].normal.dot(rightNormal), 1.0, 1e-6);

    BulletEnvironment valley;
    valley.addObstacle(twoSlopes("valley", -0.5));
    const std::vector<ContactPlane> creasePlanes = planesAt(valley, Vec3(0.0, -0.5 + 0.02, 0.0));
    ASSERT_EQ(creasePlanes.size(), 2u);
    EXPECT_NEAR(std::abs(creasePlanes[0].normal.x()), std::abs(creasePlanes[1].normal.x()), 1e-6);
    EXPECT_LT(creasePlanes[0].normal.x() * creasePlanes[1].normal.x(), 0.0); // one from each face
}

// The closed-form nearest point of a triangle (core/ClosestPointOnTriangle.h), which replaced GJK for mesh triangles:
// over a grid of points around an obtuse triangle (in its plane and off it, in every vertex, edge and face region), the
// answer lies on the triangle (barycentric coordinates within -1e-12 of [0, 1]) and is no farther than any of 5,151
// points sampled on the triangle (tolerance 1e-12 m). A wrong region (a vertex where an edge is nearer, say) fails the
// second.
TEST(ClosestPointOnTriangle, NearestPointLiesOnTheTriangleAndBeatsEverySample)
{
    const Vec3 a(0.0, 0.0, 0.0);
    const Vec3 b(1.0, 0.1, 0.0);
    const Vec3 c(-0.4, 0.2, 0.6); // obtuse at a
    std::vector<Vec3> samples;
    const int n = 100;
    for (int i = 0; i <= n; ++i)
    {
        for (int j = 0; i + j <= n; ++j)
        {
            samples.push_back(a + (b - a) * (Real(i) / n) + (c - a) * (Real(j) / n));
        }
    }
    const Vec3 normal = (b - a).cross(c - a);
    int checked = 0;
    for (int i = -4; i <= 6; ++i)
    {
        for (int j = -3; j <= 3; ++j)
        {
            for (int k = -4; k <= 5; ++k)
            {
                const Vec3 p(0.25 * i, 0.1 * j, 0.2 * k);
                const Vec3 q = closestPointOnTriangle(p, a, b, c);
                // Barycentric coordinates of q: solve q - a = v (b - a) + w (c - a) in the triangle's plane.
                const Vec3 offset = q - a;
                EXPECT_LT(std::abs(offset.dot(normal)), 1e-12) << "off the plane for p = " << p.transpose();
                const Real d00 = (b - a).squaredNorm();
                const Real d01 = (b - a).dot(c - a);
                const Real d11 = (c - a).squaredNorm();
                const Real d20 = offset.dot(b - a);
                const Real d21 = offset.dot(c - a);
                const Real det = d00 * d11 - d01 * d01;
                const Real v = (d11 * d20 - d01 * d21) / det;
                const Real w = (d00 * d21 - d01 * d20) / det;
                EXPECT_GE(v, -1e-12) << p.transpose();
                EXPECT_GE(w, -1e-12) << p.transpose();
                EXPECT_LE(v + w, 1 + 1e-12) << p.transpose();
                Real nearestSample = std::numeric_limits<Real>::infinity();
                for (const Vec3& s : samples)
                {
                    nearestSample = std::min(nearestSample, (p - s).norm());
                }
                EXPECT_LE((p - q).norm(), nearestSample + 1e-12) << p.transpose();
                ++checked;
            }
        }
    }
    EXPECT_EQ(checked, 11 * 7 * 10);
    // A degenerate triangle (its three corners on a line) still answers with a point of the segment.
    const Vec3 q = closestPointOnTriangle(Vec3(0.5, 1.0, 0.0), Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0));
    EXPECT_NEAR((q - Vec3(0.5, 0.0, 0.0)).norm(), 0.0, 1e-12);
}

namespace
{
bool sameBits(Real a, Real b)
{
    return std::memcmp(&a, &b, sizeof(Real)) == 0;
}
} // namespace

// The eight-lane face planes (AVX-512) against the scalar query they replace in detection: for each lane, whether a
// face plane answers, and then the distance, face, world normal, world point and offset, bit for bit. Box, prism and
// a hull, each turned and moved, with points inside, on faces, near edges and corners and on a face's plane exactly.
TEST(ObstacleGeometry, FacePlanesOfEightGiveTheScalarQuerysBits)
{
    if (!simdPathSupported(SimdPath::Avx512))
    {
        // Skipped without AVX-512: the eight-at-once query exists only on that path.
        GTEST_SKIP() << "this processor has no AVX-512";
    }
    const SimdPath active = activeSimdPath();
    setSimdPath(SimdPath::Avx512);
    ASSERT_TRUE(facePlanesOfEightAvailable());
    ObstacleShape hull;
    hull.kind = SolidKind::Hull;
    hull.hullPoints = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1), Vec3(0.8, 0.7, 0.9)};
    std::vector<ObstacleGeometry> shapes;
    shapes.push_back(makeObstacleGeometry(box("box", Vec3::Zero(), Vec3(0.5, 0.25, 0.75)).shape));
    shapes.push_back(makeObstacleGeometry(prism("wedge", 1.0, 1.6, 1.6, 0.5).shape));
    shapes.push_back(makeObstacleGeometry(hull));
    std::mt19937_64 random(20261128);
    std::uniform_real_distribution<Real> unit(-1, 1);
    int answered = 0;
    int left = 0;
    for (const ObstacleGeometry& g : shapes)
    {
        for (int trial = 0; trial < 200; ++trial)
        {
            Pose pose;
            pose.position = Vec3(unit(random), unit(random), unit(random));
            pose.orientation =
                trial == 0
                    ? Eigen::Quaternion<Real>::Identity()
                    : Eigen::Quaternion<Real>(unit(random), unit(random), unit(random), unit(random)).normalized();
            Vec3 centres[8];
            for (Vec3& c : centres)
            {
                c = pose.position + 1.2 * Vec3(unit(random), unit(random), unit(random));
            }
            // A point on a face's plane exactly (in the local frame), where the sign tests meet their boundary.
            const Face& face = g.faces[std::size_t(trial) % g.faces.size()];
            centres[7] = pose.orientation * (face.offset * face.normal) + pose.position;
            FacePlanesOfEight eight;
            facePlanesOfEight(g, pose, centres, eight);
            for (int lane = 0; lane < 8; ++lane)
            {
                const Vec3 local = pose.orientation.conjugate() * (centres[lane] - pose.position);
                const std::optional<FacePlaneDistance> expected = facePlaneDistance(g, local);
                ASSERT_EQ((eight.found >> lane & 1) != 0, expected.has_value()) << trial << " " << lane;
                if (!expected)
                {
                    ++left;
                    continue;
                }
                ++answered;
                const Vec3 normal = pose.orientation * g.faces[std::size_t(expected->face)].normal;
                const Vec3 point = pose.orientation * expected->point + pose.position;
                EXPECT_EQ(eight.face[lane], expected->face);
                EXPECT_TRUE(sameBits(eight.distance[lane], expected->distance)) << trial << " " << lane;
                EXPECT_TRUE(sameBits(eight.normalX[lane], normal.x()) && sameBits(eight.normalY[lane], normal.y()) &&
                            sameBits(eight.normalZ[lane], normal.z()))
                    << trial << " " << lane;
                EXPECT_TRUE(sameBits(eight.pointX[lane], point.x()) && sameBits(eight.pointY[lane], point.y()) &&
                            sameBits(eight.pointZ[lane], point.z()))
                    << trial << " " << lane;
                EXPECT_TRUE(sameBits(eight.offset[lane], normal.dot(point))) << trial << " " << lane;
            }
        }
    }
    setSimdPath(active);
    EXPECT_GT(answered, 1000);
    EXPECT_GT(left, 100);
}
