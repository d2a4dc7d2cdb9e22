// Frame coherence of mesh queries (bridge/NearbyTriangles.h): a mass that queries a mesh again from near where it
// gathered its triangles gets the same planes, bit for bit, as a query that walks the mesh's tree afresh.

#include "support/JoinedPlanes.h"

#include "bridge/BulletEnvironment.h"
#include "bridge/StlFile.h"

#include <gtest/gtest.h>

#include <random>

using namespace masse;
using namespace masse::bridge;

namespace
{
/// The vacuum cup's mould (a block with a round cavity: a fan of thin triangles on the floor, a rim rounded in
/// facets), turned and moved off the origin so that the queries work in a mesh frame that is not the world's.
ObstacleBody cupMould()
{
    ObstacleBody body;
    body.name = "mould";
    body.shape.kind = SolidKind::Mesh;
    body.shape.polygons = loadMeshFile(std::string(MASSE_SOURCE_DIR) + "/data/meshes/cup-mould.stl", "mould");
    body.path.rest.position = Vec3(0.3, -0.1, 0.05);
    body.path.rest.orientation = Eigen::Quaternion<Real>(Eigen::AngleAxis<Real>(0.4, Vec3(0.2, 1, 0.1).normalized()));
    return body;
}
} // namespace

// 3,000 masses scattered within 6 mm of the mould's vertices (where the triangles crowd: the floor's fan centre, the
// rim's facets) move for 12 frames, most of them less than the kept sphere's margin (1 mm here) a frame, some a few
// millimetres, a few a centimetre, each with a search reach of its own drawn afresh every frame. One environment keeps
// the masses' triangles from frame to frame; a new one each frame walks the tree for every mass. Their planes must
// be the same in every field, exactly.
TEST(NearbyTriangles, KeptTrianglesGiveTheSamePlanesAsAFreshWalk)
{
    BulletEnvironment kept;
    kept.addObstacle(cupMould());
    const Obstacle& mould = kept.obstacle(0);
    std::mt19937 random(7);
    std::uniform_real_distribution<Real> unit(-1, 1);
    const auto inBall = [&](Real radius)
    {
        for (;;)
        {
            const Vec3 v(unit(random), unit(random), unit(random));
            if (v.squaredNorm() <= 1)
            {
                return Vec3(radius * v);
            }
        }
    };
    const std::size_t n = 3000;
    std::vector<Vec3> x(n);
    for (Vec3& xi : x)
    {
        const Vec3& vertex = mould.geometry.vertices[std::size_t(random() % mould.geometry.vertices.size())];
        xi = mould.pose.orientation * vertex + mould.pose.position + inBall(0.006);
    }
    const Real radius = 0.002;
    std::uniform_real_distribution<Real> reachDraw(radius, 0.008);
    std::vector<Real> reach(n);
    std::size_t planesCompared = 0;
    for (int frame = 0; frame < 12; ++frame)
    {
        for (std::size_t i = 0; i < n; ++i)
        {
            reach[i] = reachDraw(random);
        }
        ContactPlaneLists fromKept;
        kept.findContacts(x, reach, radius, 0.03, fromKept);
        BulletEnvironment fresh;
        fresh.addObstacle(cupMould());
        ContactPlaneLists fromWalk;
        fresh.findContacts(x, reach, radius, 0.03, fromWalk);

        const std::vector<ContactPlane> a = test::joinedPlanes(fromKept);
        const std::vector<ContactPlane> b = test::joinedPlanes(fromWalk);
        ASSERT_EQ(a.size(), b.size()) << "frame " << frame;
        for (std::size_t k = 0; k < a.size(); ++k)
        {
            ASSERT_EQ(a[k].mass, b[k].mass) << "frame " << frame << ", plane " << k;
            EXPECT_EQ(a[k].face, b[k].face) << "mass " << a[k].mass;
            EXPECT_EQ(a[k].normal, b[k].normal) << "mass " << a[k].mass;
            EXPECT_EQ(a[k].offset, b[k].offset) << "mass " << a[k].mass;
        }
        planesCompared += a.size();

        for (std::size_t i = 0; i < n; ++i)
        {
            const std::size_t kind = i % 10;
            const Real step = kind < 6 ? 0.0008 : kind < 9 ? 0.003 : 0.01;
            x[i] += inBall(step);
        }
    }
    // Most masses are near the mould: the comparison covers many planes, not a few.
    EXPECT_GT(planesCompared, 12 * n);
}

// A mass whose position and reach are the same bits as at the last detection takes its planes from that detection
// (BulletEnvironment's still masses). Around the same mould and a box (a convex obstacle, whose face planes come eight
// masses at a time), 2,000 masses over 8 frames: a third stay where they are, a third move, a third keep their place
// but change their reach. Among still obstacles and with a box that moves (its path's keys) from frame 4 on, an
// environment kept from frame to frame must give, in every field, the planes of a new one that detects once.
TEST(NearbyTriangles, StillMassesTakeTheirPlanesFromTheLastDetectionExactly)
{
    const auto box = [](bool moving)
    {
        ObstacleBody body;
        body.name = "box";
        body.shape.kind = SolidKind::Hull;
        for (int k = 0; k < 8; ++k)
        {
            body.shape.hullPoints.emplace_back(k & 1 ? 0.02 : -0.02, k & 2 ? 0.01 : -0.01, k & 4 ? 0.02 : -0.02);
        }
        body.path.rest.position = Vec3(0.3, 0.02, 0.05);
        if (moving)
        {
            body.path.keys = {PoseKey{0.1, Vec3(0.3, 0.02, 0.05)}, PoseKey{0.4, Vec3(0.3, 0.0, 0.05)}};
        }
        return body;
    };
    std::mt19937 random(11);
    std::uniform_real_distribution<Real> unit(-1, 1);
    const std::size_t n = 2000;
    const Real radius = 0.002;
    for (const bool moving : {false, true})
    {
        BulletEnvironment kept;
        kept.addObstacle(cupMould());
        kept.addObstacle(box(moving));
        std::vector<Vec3> x(n);
        for (std::size_t i = 0; i < n; ++i)
        {
            const Obstacle& near = kept.obstacle(int(i % 2));
            const Vec3& vertex = near.geometry.vertices[std::size_t(random() % near.geometry.vertices.size())];
            x[i] = near.pose.orientation * vertex + near.pose.position +
                   0.004 * Vec3(unit(random), unit(random), unit(random));
        }
        std::vector<Real> reach(n, 0.004);
        std::size_t planesCompared = 0;
        for (int frame = 0; frame < 8; ++frame)
        {
            const Real time = 0.05 * frame;
            kept.setTime(time);
            ContactPlaneLists fromKept;
            kept.findContacts(x, reach, radius, 0.05, fromKept);
            BulletEnvironment fresh;
            fresh.addObstacle(cupMould());
            fresh.addObstacle(box(moving));
            fresh.setTime(time);
            ContactPlaneLists fromFresh;
            fresh.findContacts(x, reach, radius, 0.05, fromFresh);

            const std::vector<ContactPlane> a = test::joinedPlanes(fromKept);
            const std::vector<ContactPlane> b = test::joinedPlanes(fromFresh);
            ASSERT_EQ(a.size(), b.size()) << "frame " << frame << (moving ? ", moving box" : "");
            for (std::size_t k = 0; k < a.size(); ++k)
            {
                ASSERT_EQ(a[k].mass, b[k].mass) << "frame " << frame << ", plane " << k;
                EXPECT_EQ(a[k].obstacle, b[k].obstacle) << "mass " << a[k].mass;
                EXPECT_EQ(a[k].face, b[k].face) << "mass " << a[k].mass;
                EXPECT_EQ(a[k].normal, b[k].normal) << "mass " << a[k].mass;
                EXPECT_EQ(a[k].offset, b[k].offset) << "mass " << a[k].mass;
                EXPECT_EQ(a[k].velocity, b[k].velocity) << "mass " << a[k].mass;
            }
            planesCompared += a.size();
            for (std::size_t i = 0; i < n; ++i)
            {
                if (i % 3 == 1)
                {
                    x[i] += 0.001 * Vec3(unit(random), unit(random), unit(random));
                }
                else if (i % 3 == 2)
                {
                    reach[i] = 0.004 * (1.5 + unit(random));
                }
            }
        }
        EXPECT_GT(planesCompared, 4 * n) << "most masses should be near an obstacle";
    }
}
