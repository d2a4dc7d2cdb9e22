// The eight-lane nearest points on a mesh's triangles (bridge/NearestOnTrianglesOfEight.h) against the scalar code
// they replace in detection (TriangleTest's box and plane tests, closestPointOnTriangle, the distance and direction to
// the centre), lane by lane and bit for bit.

#include "support/TestSystems.h"

#include "bridge/NearestOnTrianglesOfEight.h"
#include "bridge/ObstacleGeometry.h"
#include "bridge/StlFile.h"
#include "core/contact/ClosestPointOnTriangle.h"
#include "core/forces/SimdPath.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>

using namespace masse;
using namespace masse::bridge;

namespace
{
bool sameBits(Real a, Real b)
{
    return std::memcmp(&a, &b, sizeof(Real)) == 0;
}

/// TriangleTest's two tests, as written there: whether the triangle is turned away.
bool turnedAway(const Vec3& p, const std::array<Vec3, 3>& t, const Vec3& normal, Real rejectBeyond)
{
    const Vec3 outside =
        (t[0].cwiseMin(t[1]).cwiseMin(t[2]) - p).cwiseMax(p - t[0].cwiseMax(t[1]).cwiseMax(t[2])).cwiseMax(Real(0));
    return outside.squaredNorm() > rejectBeyond * rejectBeyond || std::abs(normal.dot(p - t[0])) > rejectBeyond;
}

Vec3 unitNormal(const std::array<Vec3, 3>& t)
{
    const Vec3 n = (t[1] - t[0]).cross(t[2] - t[0]);
    const Real length = n.norm();
    return length > 0 ? Vec3(n / length) : Vec3(Vec3::Zero());
}

/// Checks every lane of one call against the scalar code. Returns the lanes whose nearest point was compared.
int expectScalarBits(const std::vector<std::array<Vec3, 3>>& corners, const std::vector<Vec3>& normals,
                     const std::vector<std::int32_t>& triangles, const Vec3& p, Real rejectBeyond)
{
    NearestOnTrianglesOfEight eight;
    nearestOnTrianglesOfEight(corners, normals, triangles.data(), int(triangles.size()), p, rejectBeyond, eight);
    int compared = 0;
    for (std::size_t lane = 0; lane < 8; ++lane)
    {
        const bool near = (eight.near >> lane & 1) != 0;
        const bool degenerate = (eight.degenerate >> lane & 1) != 0;
        if (lane >= triangles.size())
        {
            EXPECT_FALSE(near || degenerate) << "lane " << lane << " past the count";
            continue;
        }
        const auto t = std::size_t(triangles[lane]);
        const bool away = turnedAway(p, corners[t], normals[t], rejectBeyond);
        EXPECT_EQ(near || degenerate, !away) << "triangle " << t;
        if (!near)
        {
            continue;
        }
        const Vec3 expected = closestPointOnTriangle(p, corners[t][0], corners[t][1], corners[t][2]);
        EXPECT_TRUE(sameBits(eight.nearestX[lane], expected.x()) && sameBits(eight.nearestY[lane], expected.y()) &&
                    sameBits(eight.nearestZ[lane], expected.z()))
            << "triangle " << t << ": (" << eight.nearestX[lane] << ", " << eight.nearestY[lane] << ", "
            << eight.nearestZ[lane] << ") against (" << expected.transpose() << ")";
        // TriangleTest::take's distance and direction from the point to the centre.
        const Vec3 offset = p - expected;
        const Real gap = offset.norm();
        EXPECT_TRUE(sameBits(eight.gap[lane], gap))
            << "triangle " << t << ": " << eight.gap[lane] << " against " << gap;
        if (gap > 0)
        {
            const Vec3 direction = offset / gap;
            EXPECT_TRUE(sameBits(eight.directionX[lane], direction.x()) &&
                        sameBits(eight.directionY[lane], direction.y()) &&
                        sameBits(eight.directionZ[lane], direction.z()))
                << "triangle " << t << ": direction (" << eight.directionX[lane] << ", " << eight.directionY[lane]
                << ", " << eight.directionZ[lane] << ") against (" << direction.transpose() << ")";
        }
        ++compared;
    }
    return compared;
}

/// The checks of the test below, on the active path.
void expectEachLaneHasTheScalarCodesBits()
{
    ASSERT_TRUE(nearestOnTrianglesOfEightAvailable());

    std::mt19937_64 random(20261207);
    std::uniform_real_distribution<Real> unit(-1, 1);
    std::vector<std::array<Vec3, 3>> corners;
    for (int k = 0; k < 400; ++k)
    {
        const Vec3 a(unit(random), unit(random), unit(random));
        Vec3 b(unit(random), unit(random), unit(random));
        Vec3 c(unit(random), unit(random), unit(random));
        switch (k % 8)
        {
        case 0:
            c = a + Real(0.37) * (b - a); // collinear
            break;
        case 1:
            b = a; // a point
            c = a;
            break;
        case 2:
            c = a + Real(1e-7) * (c - a); // a sliver
            break;
        default:
            break;
        }
        corners.push_back({a, b, c});
    }
    std::vector<Vec3> normals;
    for (const auto& t : corners)
    {
        normals.push_back(unitNormal(t));
    }
    int compared = 0;
    for (int trial = 0; trial < 4000; ++trial)
    {
        const int count = 1 + trial % 8;
        std::vector<std::int32_t> triangles;
        for (int lane = 0; lane < count; ++lane)
        {
            triangles.push_back(std::int32_t(random() % corners.size()));
        }
        const auto& t = corners[std::size_t(triangles[0])];
        Vec3 p;
        switch (trial % 5)
        {
        case 0:
            p = t[std::size_t(trial / 5 % 3)]; // on a corner
            break;
        case 1:
            p = Real(0.5) * (t[0] + t[1]); // on an edge
            break;
        case 2:
            p = (t[0] + t[1] + t[2]) / 3; // on the face
            break;
        default:
            p = Vec3(unit(random), unit(random), unit(random)) * Real(1.5);
            break;
        }
        const Real rejectBeyond = std::array<Real, 4>{0.05, 0.3, 1.0, 4.0}[std::size_t(trial % 4)];
        compared += expectScalarBits(corners, normals, triangles, p, rejectBeyond);
    }
    EXPECT_GT(compared, 4000);

    // The cup's mould: its floor's fan of thin triangles and its rim's facets, centres within 6 mm of its vertices.
    ObstacleShape mould;
    mould.kind = SolidKind::Mesh;
    mould.polygons = loadMeshFile(std::string(MASSE_SOURCE_DIR) + "/data/meshes/cup-mould.stl", "mould");
    const ObstacleGeometry g = makeObstacleGeometry(mould);
    std::vector<std::int32_t> all(g.triangleCorners.size());
    for (std::size_t k = 0; k < all.size(); ++k)
    {
        all[k] = std::int32_t(k);
    }
    int mouldCompared = 0;
    for (int trial = 0; trial < 2000; ++trial)
    {
        const auto& t = g.triangleCorners[random() % g.triangleCorners.size()];
        const Vec3 p = t[std::size_t(trial % 3)] + Real(0.006) * Vec3(unit(random), unit(random), unit(random));
        const std::size_t first = random() % (all.size() - 8);
        const std::vector<std::int32_t> eight(all.begin() + std::ptrdiff_t(first),
                                              all.begin() + std::ptrdiff_t(first + 8));
        mouldCompared += expectScalarBits(g.triangleCorners, g.triangleNormals, eight, p, Real(0.004));
    }
    EXPECT_GT(mouldCompared, 0);
}
} // namespace

// Random triangles (some thin, some collinear, some a point) against centres anywhere around them, on their corners,
// edges and faces exactly, with search radii from a fraction of the triangle to all of it, one to eight lanes a call;
// and the vacuum cup's mould with centres near its vertices. Every lane: turned away exactly when the scalar tests turn
// it away, and otherwise the bits of the scalar nearest point, its distance and its direction (a degenerate triangle is
// left to the scalar code).
TEST(NearestOnTrianglesOfEight, EachLaneHasTheScalarCodesBits)
{
    if (!simdPathSupported(SimdPath::Avx2))
    {
        // Skipped without AVX2: the eight-at-once test exists only on the AVX2 and AVX-512 paths.
        GTEST_SKIP() << "this processor has no AVX2";
    }
    const test::SimdPathGuard guard;
    for (const SimdPath path : {SimdPath::Avx2, SimdPath::Avx512})
    {
        if (simdPathSupported(path))
        {
            SCOPED_TRACE(simdPathName(path));
            setSimdPath(path);
            expectEachLaneHasTheScalarCodesBits();
        }
    }
}
