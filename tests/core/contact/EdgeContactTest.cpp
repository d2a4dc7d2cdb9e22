// The sheet's edges and triangles against obstacle edges and corners (issue 12, point 1): one touch of each kind
// against its analytic outcome, the sharp features Bullet's shapes give, and the knife-edge scene with and without the
// contact.

#include "core/contact/EdgeContact.h"
#include "bridge/ObstacleFeatures.h"
#include "core/InputError.h"
#include "core/contact/ClosestPointOnTriangle.h"
#include "core/contact/ClosestPointsOfSegments.h"
#include "core/forces/Energy.h"
#include "scene/Scene.h"
#include "scene/SceneFile.h"
#include "scene/shapes/BoxShape.h"
#include "scene/shapes/PrismShape.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>

using namespace masse;
using namespace masse::scene;

namespace
{
const std::string source = MASSE_SOURCE_DIR;

/// A detector that lists what it is given, whatever the positions: the test sees the core's own measurement.
class GivenPairs final : public EdgeContactDetector
{
public:
    EdgeContactCandidates candidates;
    void setSurface(const SheetSurface& /*surface*/) override {}
    void findCandidates(const std::vector<Vec3>& /*x*/, const std::vector<Real>& /*reach*/, Real /*radius*/,
                        Real /*time*/, Real /*dt*/, EdgeContactCandidates& out) override
    {
        out = candidates;
    }
};

/// The ridge of a knife along z through the origin (apex angle 20 degrees): its two faces' outward normals.
ObstacleEdge knifeRidge()
{
    const Real half = 10 * M_PI / 180;
    ObstacleEdge ridge;
    ridge.start = Vec3(0, 0, -1);
    ridge.end = Vec3(0, 0, 1);
    ridge.normals[0] = Vec3(-std::cos(half), std::sin(half), 0);
    ridge.normals[1] = Vec3(std::cos(half), std::sin(half), 0);
    ridge.obstacle = 0;
    return ridge;
}

/// The knife's ridge, listed against the sheet's edge 0.
GivenPairs ridgeAgainstEdge0()
{
    GivenPairs pairs;
    pairs.candidates.edges = {knifeRidge()};
    pairs.candidates.edgePairs = {{0, 0}};
    return pairs;
}

/// A one-layer 2x1x2 sheet (masses 0 and 1 in its first row: its edge 0) of unequal masses; masses 2 and 3 far away.
struct TwoMasses
{
    Lattice lattice;
    MassSpringSystem sheet;
    Real radius = 0.01;

    TwoMasses(const Vec3& first, const Vec3& second, const Vec3& velocity)
    {
        LatticeSpec spec;
        spec.structure = Structure::Square2D;
        spec.countX = 2;
        spec.layers = 1;
        spec.countZ = 2;
        spec.minCorner = Vec3(0, 0, 0);
        spec.maxCorner = Vec3(0.1, 0, 0.1);
        lattice = buildLattice(spec);
        sheet = makeSheet(lattice, SheetParams{});
        Particles& p = sheet.particles;
        p.position = {first, second, Vec3(5, 5, 5), Vec3(6, 7, 5)};
        for (std::size_t i = 0; i < p.size(); ++i)
        {
            p.mass[i] = 0.001 * Real(1 + i);
            p.inverseMass[i] = 1 / p.mass[i];
            p.velocity[i] = i < 2 ? velocity : Vec3::Zero();
            p.force[i].setZero();
        }
        sheet.forces.gravity.setZero();
    }

    /// Mass 1 as heavy as mass 0, so that a push shared by the edge's weights moves it level.
    void equalMasses()
    {
        sheet.particles.mass[1] = sheet.particles.mass[0];
        sheet.particles.inverseMass[1] = sheet.particles.inverseMass[0];
    }
};

ContactSettings friction(Real mu, Real radius)
{
    ContactSettings settings;
    settings.response = ContactResponse::Friction;
    settings.friction = mu;
    settings.radius = radius;
    return settings;
}

/// The sheet edge's point nearest the ridge, and the ridge's.
struct Nearest
{
    Real s;
    Vec3 sheet;
    Vec3 ridge;
};

Nearest nearestToRidge(const Particles& p, const ObstacleEdge& ridge)
{
    const SegmentParameters at = closestPointsOfSegments(p.position[0], p.position[1], ridge.start, ridge.end);
    return {at.s, p.position[0] + at.s * (p.position[1] - p.position[0]),
            ridge.start + at.t * (ridge.end - ridge.start)};
}
} // namespace

// A sheet edge falling at 1 m/s and sliding at 2 m/s along a ridge, half a radius above it, crossing it a quarter of
// the way along: after the substep's response its point over the ridge is exactly the radius above it (1e-12 m) and
// has stopped falling (inelastic), its slip has lost mu times the 1 m/s (mu 0.3: 2 -> 1.7 m/s), the impulse is shared
// by the weights over the inverse masses (analytic: dv_k = w_k / m_k * J, J = 1 / sum(w^2 / m)) and the kinetic energy
// has not grown.
TEST(EdgeContact, AnEdgeOnARidgeStopsInelasticallyWithCoulombFriction)
{
    const Real radius = 0.01;
    TwoMasses sheet(Vec3(-0.01, 0.5 * radius, 0.2), Vec3(0.03, 0.5 * radius, 0.2), Vec3(0, -1, 2));
    Particles& p = sheet.sheet.particles;
    GivenPairs pairs = ridgeAgainstEdge0();
    EdgeContact edges(sheet.lattice, pairs, friction(0.3, radius));
    ASSERT_EQ(edges.surface().edges[0], (Edge{0, 1}));
    StepContext context;
    const Real energyBefore = kineticEnergy(p);
    const Real w0 = 0.75;
    const Real w1 = 0.25;
    edges.beginFrame(sheet.sheet, context, 0, 0.01);
    edges.afterSubstep(sheet.sheet, context, 0.001, 0.001);

    ASSERT_EQ(edges.report().lastSubstep, 1u);
    const Vec3 point = w0 * p.position[0] + w1 * p.position[1];
    EXPECT_NEAR(point.x(), 0, 1e-12);
    EXPECT_NEAR(point.y(), radius, 1e-12);
    const Vec3 pointVelocity = w0 * p.velocity[0] + w1 * p.velocity[1];
    EXPECT_NEAR(pointVelocity.y(), 0, 1e-12);
    EXPECT_NEAR(pointVelocity.z(), 2 - 0.3 * 1, 1e-12);
    const Real normalImpulse = 1 / (w0 * w0 / p.mass[0] + w1 * w1 / p.mass[1]);
    EXPECT_NEAR(p.velocity[0].y(), -1 + w0 / p.mass[0] * normalImpulse, 1e-12);
    EXPECT_NEAR(p.velocity[1].y(), -1 + w1 / p.mass[1] * normalImpulse, 1e-12);
    EXPECT_LT(kineticEnergy(p), energyBefore);
    EXPECT_EQ(edges.report().firstObstacle, 0);
}

// An edge already inside the knife (0.3 radius under the ridge, behind both faces) is pushed back out the way it came,
// to a radius above the ridge, not further in; a second substep finds it there and leaves it there.
TEST(EdgeContact, AnEdgeInsideTheObstacleIsPushedBackOutThroughTheRidge)
{
    const Real radius = 0.01;
    TwoMasses sheet(Vec3(-0.02, -0.3 * radius, 0.1), Vec3(0.02, -0.3 * radius, 0.1), Vec3::Zero());
    Particles& p = sheet.sheet.particles;
    sheet.equalMasses(); // so the edge rises level
    GivenPairs pairs = ridgeAgainstEdge0();
    EdgeContact edges(sheet.lattice, pairs, friction(0.3, radius));
    StepContext context;
    edges.beginFrame(sheet.sheet, context, 0, 0.01);
    edges.afterSubstep(sheet.sheet, context, 0.001, 0.001);
    ASSERT_EQ(edges.report().lastSubstep, 1u);
    const Nearest nearest = nearestToRidge(p, knifeRidge());
    EXPECT_NEAR(nearest.sheet.y(), radius, 1e-12);
    EXPECT_NEAR(nearest.sheet.x(), 0, 1e-12);

    edges.afterSubstep(sheet.sheet, context, 0.001, 0.002);
    EXPECT_NEAR(nearestToRidge(p, knifeRidge()).sheet.y(), radius, 1e-12);
    EXPECT_EQ(p.velocity[0], Vec3::Zero());
}

// One step carries an edge from a radius above the knife's ridge to two radii under it, past the radius within which
// a pair touches: it came through the ridge within the frame, so it is pushed back out the way it came, to a radius
// above the ridge. An edge that was already under the ridge when the frame began is left alone (it did not come
// through this ridge now; under a non-convex obstacle's edge it may be outside).
TEST(EdgeContact, AnEdgeCarriedOverTheRidgeInOneStepIsPushedBackOut)
{
    const Real radius = 0.01;
    for (const bool aboveAtStart : {true, false})
    {
        const Real startHeight = aboveAtStart ? radius : -2 * radius;
        TwoMasses sheet(Vec3(-0.02, startHeight, 0.1), Vec3(0.02, startHeight, 0.1), Vec3::Zero());
        Particles& p = sheet.sheet.particles;
        sheet.equalMasses();
        GivenPairs pairs = ridgeAgainstEdge0();
        EdgeContact edges(sheet.lattice, pairs, friction(0.3, radius));
        StepContext context;
        edges.beginFrame(sheet.sheet, context, 0, 0.01);
        for (std::size_t i = 0; i < 2; ++i)
        {
            p.position[i].y() = -2 * radius; // where the solve left it
            p.velocity[i] = Vec3(0, -3 * radius / 0.01, 0);
        }
        edges.afterSubstep(sheet.sheet, context, 0.01, 0.01);
        const Nearest nearest = nearestToRidge(p, knifeRidge());
        if (aboveAtStart)
        {
            EXPECT_EQ(edges.report().lastSubstep, 1u);
            EXPECT_NEAR(nearest.sheet.y(), radius, 1e-12);
            EXPECT_NEAR(p.velocity[0].y(), 0, 1e-12) << "inelastic: the approach is stopped";
        }
        else
        {
            EXPECT_EQ(edges.report().lastSubstep, 0u);
            EXPECT_EQ(nearest.sheet.y(), -2 * radius);
        }
    }
}

// An apex under a triangle's middle, half a radius below it, while the triangle falls at 1 m/s: the triangle ends a
// radius above the apex (its point at the touch's weights, 1e-12 m), that point stopped; frictionless, nothing moves
// sideways. A triangle whose
// nearest point to the apex is one of its masses is left to the mass's own contact.
TEST(EdgeContact, AnApexUnderATrianglePushesItOutInelastically)
{
    const Real radius = 0.01;
    LatticeSpec spec;
    spec.structure = Structure::Square2D;
    spec.countX = 2;
    spec.layers = 1;
    spec.countZ = 2;
    spec.minCorner = Vec3(-0.05, 0.5 * radius, -0.05);
    spec.maxCorner = Vec3(0.05, 0.5 * radius, 0.05);
    const Lattice lattice = buildLattice(spec);
    MassSpringSystem sheet = makeSheet(lattice, SheetParams{});
    Particles& p = sheet.particles;
    sheet.forces.gravity.setZero();
    for (std::size_t i = 0; i < p.size(); ++i)
    {
        p.velocity[i] = Vec3(0, -1, 0);
        p.force[i].setZero();
    }
    GivenPairs pairs;
    ObstacleCorner apex;
    apex.point = Vec3(0.01, 0, -0.02); // under triangle 0's inside, off its diagonal
    apex.firstNormal = 0;
    apex.normalCount = 4;
    const Real tilt = std::sin(10 * M_PI / 180);
    pairs.candidates.cornerNormals = {Vec3(1, tilt, 0).normalized(), Vec3(-1, tilt, 0).normalized(),
                                      Vec3(0, tilt, 1).normalized(), Vec3(0, tilt, -1).normalized()};
    pairs.candidates.corners = {apex};
    const std::vector<Triangle> triangles = sheetSurface(lattice).triangles;
    const auto under = std::find_if(triangles.begin(), triangles.end(),
                                    [&](const Triangle& t)
                                    {
                                        const Vec3 w = closestPointWeights(apex.point, p.position[t[0]],
                                                                           p.position[t[1]], p.position[t[2]]);
                                        return w.minCoeff() > 0;
                                    });
    ASSERT_NE(under, triangles.end());
    const Index triangle = Index(under - triangles.begin());
    pairs.candidates.cornerPairs = {{triangle, 0}};
    EdgeContact edges(lattice, pairs, friction(0, radius));
    StepContext context;
    const Real energyBefore = kineticEnergy(p);
    const Triangle& t = triangles[triangle];
    const Vec3 w = closestPointWeights(apex.point, p.position[t[0]], p.position[t[1]], p.position[t[2]]);
    edges.beginFrame(sheet, context, 0, 0.01);
    edges.afterSubstep(sheet, context, 0.001, 0.001);
    ASSERT_EQ(edges.report().lastSubstep, 1u);
    const Vec3 point = w[0] * p.position[t[0]] + w[1] * p.position[t[1]] + w[2] * p.position[t[2]];
    EXPECT_NEAR((point - apex.point).norm(), radius, 1e-12);
    EXPECT_NEAR(point.y() - apex.point.y(), radius, 1e-12);
    const Vec3 velocity = w[0] * p.velocity[t[0]] + w[1] * p.velocity[t[1]] + w[2] * p.velocity[t[2]];
    EXPECT_NEAR(velocity.y(), 0, 1e-12);
    for (std::size_t i = 0; i < p.size(); ++i)
    {
        EXPECT_NEAR(p.velocity[i].x(), 0, 1e-12);
        EXPECT_NEAR(p.velocity[i].z(), 0, 1e-12);
    }
    EXPECT_LT(kineticEnergy(p), energyBefore);

    // The apex right under a mass of the level triangle: that is the mass's contact, not this one's.
    p.position = lattice.position;
    apex.point = p.position[t[0]] - Vec3(0, 0.5 * radius, 0);
    pairs.candidates.corners = {apex};
    EdgeContact atMass(lattice, pairs, friction(0, radius));
    const std::vector<Vec3> before = p.position;
    atMass.beginFrame(sheet, context, 0, 0.01);
    atMass.afterSubstep(sheet, context, 0.001, 0.001);
    EXPECT_EQ(atMass.report().lastSubstep, 0u);
    EXPECT_EQ(p.position, before);
}

// The faces the edge contact meets obstacles with (SheetFaces::Volume), for every structure and layer count: the bottom
// and top layers with the rim are one closed surface (each edge in exactly two of their triangles; without the rim the
// layers' border edges are in one), every spring of the sheet between two layers or in its bottom or top layer is one
// of the edges (without the rim and the inner faces the springs between the layers are none, so a ridge could cut
// them), and the patches hold each triangle once.
TEST(EdgeContact, TheSheetsFacesHaveEverySpringAsAnEdge)
{
    const auto edgeUses = [](const std::vector<Triangle>& triangles)
    {
        std::map<Edge, int> uses;
        for (const Triangle& t : triangles)
        {
            for (int k = 0; k < 3; ++k)
            {
                const Index a = t[std::size_t(k)];
                const Index b = t[std::size_t((k + 1) % 3)];
                ++uses[{std::min(a, b), std::max(a, b)}];
            }
        }
        return uses;
    };
    for (const Structure structure : {Structure::SaMM, Structure::SLaMM, Structure::TRiMM})
    {
        for (const int layers : {2, 3})
        {
            LatticeSpec spec;
            spec.structure = structure;
            spec.countX = 9;
            spec.countZ = 6;
            spec.layers = layers;
            const Lattice lattice = buildLattice(spec);
            const std::string name = std::string(structureName(structure)) + " " + std::to_string(layers) + " layers";

            const SheetSurface outer = sheetSurface(lattice);
            std::vector<Triangle> closed = outer.triangles;
            EXPECT_TRUE(std::ranges::any_of(edgeUses(closed), [](const auto& use) { return use.second == 1; })) << name;
            for (const std::vector<Triangle>& strip : rimStrips(lattice))
            {
                closed.insert(closed.end(), strip.begin(), strip.end());
            }
            for (const auto& [edge, count] : edgeUses(closed))
            {
                EXPECT_EQ(count, 2) << name << ": edge " << edge[0] << "-" << edge[1];
            }

            const SheetSurface volume = sheetSurface(lattice, SheetFaces::Volume);
            const auto uses = edgeUses(volume.triangles);
            EXPECT_EQ(uses.size(), volume.edges.size()) << name;
            int between = 0;
            for (const SpringEnds& spring : lattice.springs.ends())
            {
                const int a = lattice.coord[spring.a].layer;
                const int b = lattice.coord[spring.b].layer;
                if (a == b && a != 0 && a != layers - 1)
                {
                    continue; // a middle layer's own springs
                }
                between += a != b ? 1 : 0;
                const Edge edge{std::min(spring.a, spring.b), std::max(spring.a, spring.b)};
                EXPECT_TRUE(std::binary_search(volume.edges.begin(), volume.edges.end(), edge))
                    << name << ": spring " << spring.a << "-" << spring.b;
                if (a != b)
                {
                    EXPECT_FALSE(std::binary_search(outer.edges.begin(), outer.edges.end(), edge)) << name;
                }
            }
            EXPECT_GT(between, 0) << name;

            std::vector<Index> patched = volume.patchTriangles;
            std::sort(patched.begin(), patched.end());
            ASSERT_EQ(patched.size(), volume.triangles.size()) << name;
            for (std::size_t k = 0; k < patched.size(); ++k)
            {
                EXPECT_EQ(patched[k], Index(k)) << name;
            }
            EXPECT_EQ(volume.patchStart.back(), volume.patchTriangles.size()) << name;
        }
    }
}

// Which features count as sharp: a box's 12 edges and 8 corners, a prism's 9 and 6 (each edge with its two faces'
// outward normals, each corner with its three faces').
TEST(EdgeContact, BoxesAndPrismsHaveEverySharpEdgeAndCorner)
{
    const Vec3 half(0.5, 0.2, 0.3);
    const bridge::ObstacleGeometry boxGeometry = bridge::makeObstacleGeometry(scene::boxSolid(half));
    const bridge::SharpFeatures boxFeatures = bridge::sharpFeatures(boxGeometry);
    EXPECT_EQ(boxFeatures.edges.size(), 12u);
    EXPECT_EQ(boxFeatures.corners.size(), 8u);
    for (const bridge::SharpEdge& edge : boxFeatures.edges)
    {
        EXPECT_NEAR(edge.normals[0].dot(edge.normals[1]), 0, 1e-12);
        // The edge's middle lies on both faces' planes: it is where they meet.
        const Vec3 middle =
            0.5 * (boxGeometry.vertices[std::size_t(edge.start)] + boxGeometry.vertices[std::size_t(edge.end)]);
        EXPECT_NEAR(edge.normals[0].dot(middle), edge.normals[0].cwiseAbs().dot(half), 1e-12);
        EXPECT_NEAR(edge.normals[1].dot(middle), edge.normals[1].cwiseAbs().dot(half), 1e-12);
    }
    for (const bridge::SharpCorner& corner : boxFeatures.corners)
    {
        EXPECT_EQ(corner.normalCount, 3u);
    }

    scene::PrismSize prism;
    prism.width = 0.2;
    prism.height = 0.6;
    prism.length = 1;
    const bridge::SharpFeatures prismFeatures =
        bridge::sharpFeatures(bridge::makeObstacleGeometry(scene::prismSolid(prism)));
    EXPECT_EQ(prismFeatures.edges.size(), 9u);
    EXPECT_EQ(prismFeatures.corners.size(), 6u);
}

namespace
{
/// A convex obstacle as its faces' planes in the world: depth(p) = min over faces of (offset - normal . p), positive
/// inside. The deepest point of a segment or a triangle is found exactly: depth is the least of affine functions, so
/// its largest value over a segment (a triangle) is at an end (a corner) or where two (three) of them are equal.
struct ConvexSolid
{
    std::vector<Vec3> normals;
    std::vector<Real> offsets;

    explicit ConvexSolid(const bridge::Obstacle& obstacle)
    {
        for (const bridge::Face& face : obstacle.geometry.faces)
        {
            const Vec3 normal = obstacle.pose.orientation * face.normal;
            normals.push_back(normal);
            offsets.push_back(face.offset + normal.dot(obstacle.pose.position));
        }
    }

    Real depth(const Vec3& p) const
    {
        Real least = std::numeric_limits<Real>::infinity();
        for (std::size_t f = 0; f < normals.size(); ++f)
        {
            least = std::min(least, offsets[f] - normals[f].dot(p));
        }
        return least;
    }

    Real deepestOnSegment(const Vec3& a, const Vec3& b) const
    {
        Real deepest = std::max(depth(a), depth(b));
        for (std::size_t f = 0; f < normals.size(); ++f)
        {
            for (std::size_t g = f + 1; g < normals.size(); ++g)
            {
                // offset_f - n_f . (a + t (b - a)) equal for f and g
                const Real slope = (normals[f] - normals[g]).dot(b - a);
                if (slope == 0)
                {
                    continue;
                }
                const Real t = (offsets[f] - offsets[g] - (normals[f] - normals[g]).dot(a)) / slope;
                if (t > 0 && t < 1)
                {
                    deepest = std::max(deepest, depth(a + t * (b - a)));
                }
            }
        }
        return deepest;
    }

    Real deepestOnTriangle(const Vec3& a, const Vec3& b, const Vec3& c) const
    {
        Real deepest = std::max({deepestOnSegment(a, b), deepestOnSegment(b, c), deepestOnSegment(c, a)});
        const Vec3 e1 = b - a;
        const Vec3 e2 = c - a;
        const std::size_t n = normals.size();
        for (std::size_t f = 0; f < n; ++f)
        {
            for (std::size_t g = f + 1; g < n; ++g)
            {
                for (std::size_t h = g + 1; h < n; ++h)
                {
                    // Where faces f, g and h are equally deep: two linear equations in (u, v), p = a + u e1 + v e2.
                    const Vec3 fg = normals[f] - normals[g];
                    const Vec3 fh = normals[f] - normals[h];
                    const Real m00 = fg.dot(e1), m01 = fg.dot(e2), m10 = fh.dot(e1), m11 = fh.dot(e2);
                    const Real r0 = offsets[f] - offsets[g] - fg.dot(a);
                    const Real r1 = offsets[f] - offsets[h] - fh.dot(a);
                    const Real determinant = m00 * m11 - m01 * m10;
                    if (determinant == 0)
                    {
                        continue;
                    }
                    const Real u = (r0 * m11 - m01 * r1) / determinant;
                    const Real v = (m00 * r1 - r0 * m10) / determinant;
                    if (u > 0 && v > 0 && u + v < 1)
                    {
                        deepest = std::max(deepest, depth(a + u * e1 + v * e2));
                    }
                }
            }
        }
        return deepest;
    }
};

struct KnifeOutcome
{
    Real deepestSpring = 0;   ///< m, the deepest any spring segment ended a step inside the knife
    Real deepestTriangle = 0; ///< m, the same for the surface triangles
    Real spacing = 0;
    std::uint64_t touches = 0;
    Real lowestMass = std::numeric_limits<Real>::infinity(); ///< m, the lowest y any mass reached
};

/// The knife-edge scene, its sheet `size` masses a side (0: the scene's).
KnifeOutcome dropOnKnife(bool edgeCollision, int size = 0, std::optional<IntegratorKind> integrator = std::nullopt)
{
    SceneSpec spec = loadScene(source + "/data/scenes/knife-edge.json");
    spec.edgeCollision = edgeCollision;
    if (integrator)
    {
        spec.time.integrator = *integrator;
    }
    if (size > 0)
    {
        spec.sheet.lattice.countX = size;
        spec.sheet.lattice.countZ = size;
    }
    Scene scene(spec);
    const ConvexSolid knife(scene.environment().obstacle(scene.environment().findObstacle("knife")));
    const std::vector<Triangle> triangles = sheetSurface(scene.lattice()).triangles;
    KnifeOutcome outcome;
    outcome.spacing = scene.lattice().spacingX;
    while (!scene.finished())
    {
        scene.step();
        const std::vector<Vec3>& x = scene.system().particles.position;
        for (const SpringEnds& spring : scene.lattice().springs.ends())
        {
            outcome.deepestSpring = std::max(outcome.deepestSpring, knife.deepestOnSegment(x[spring.a], x[spring.b]));
        }
        for (const Triangle& t : triangles)
        {
            outcome.deepestTriangle =
                std::max(outcome.deepestTriangle, knife.deepestOnTriangle(x[t[0]], x[t[1]], x[t[2]]));
        }
        for (const Vec3& position : x)
        {
            outcome.lowestMass = std::min(outcome.lowestMass, position.y());
        }
    }
    outcome.touches = scene.edgeContact() ? scene.edgeContact()->report().total : 0;
    return outcome;
}
} // namespace

// The knife: a sheet dropped onto a prism with a 20 degree apex whose ridge lies between two columns of masses
// (6.7 cm apart, spheres of 1 cm). With the edge contact, no spring segment and no surface triangle ends a step inside
// the prism by more than 1% of the spacing (measured: none inside at all) and the sheet hangs over the ridge (its
// halves fall well below it); without it the ridge passes between the masses and the same check fails by far (the
// springs across the ridge end steps up to 9.3 mm inside, measured from the knife's nearest face: 14 times the bound).
TEST(EdgeContact, SheetDrapedOverAKnifeEdgeStaysOutOfIt)
{
    const KnifeOutcome without = dropOnKnife(false);
    EXPECT_GT(without.deepestSpring, 0.01 * without.spacing) << "without edge contact the ridge should cut the sheet";
    EXPECT_GT(without.deepestTriangle, 0.01 * without.spacing);

    const KnifeOutcome with = dropOnKnife(true);
    EXPECT_GT(with.touches, 0u) << "the sheet never met the ridge: the scene does not test the edge contact";
    EXPECT_LE(with.deepestSpring, 0.01 * with.spacing);
    EXPECT_LE(with.deepestTriangle, 0.01 * with.spacing);
    EXPECT_LT(with.lowestMass, -0.2) << "the sheet should fold over the ridge, its halves hanging down the knife";
    std::cout << "deepest spring / triangle inside the knife: without " << without.deepestSpring << " / "
              << without.deepestTriangle << " m, with " << with.deepestSpring << " / " << with.deepestTriangle
              << " m (1% of the spacing: " << 0.01 * with.spacing << " m); touches " << with.touches << "\n";
}

// The same at 48x2x48, where the spacing (2.1 cm) is below the spheres' diameter and the border rows crumple over the
// ridge: no spring or surface triangle ends a step inside by more than 1% of the spacing (measured: none inside). With
// only the bottom and top layers' faces, springs joining the layers ended steps 1.2 mm inside (a border one), 0.86 mm
// with the rim added (one a few rows in): six and four times the bound; with the faces inside the sheet, none.
TEST(EdgeContact, FinerSheetDrapedOverAKnifeEdgeKeepsEverySpringOut)
{
    const KnifeOutcome with = dropOnKnife(true, 48);
    EXPECT_GT(with.touches, 0u);
    EXPECT_LE(with.deepestSpring, 0.01 * with.spacing);
    EXPECT_LE(with.deepestTriangle, 0.01 * with.spacing);
    EXPECT_LT(with.lowestMass, -0.2);
    std::cout << "48x2x48: deepest spring / triangle inside the knife " << with.deepestSpring << " / "
              << with.deepestTriangle << " m (1% of the spacing: " << 0.01 * with.spacing << " m)\n";
}

// The knife at 48x2x48 under the implicit integrators, one solve a 0.03 s frame: the edge contact acts after each
// solve, and pushes back out a sheet edge the solve carried over the ridge deeper than a radius (it was outside the
// ridge's faces at the frame's start), so again no spring or surface triangle ends a step inside by more than 1% of
// the spacing (measured: none inside, backward Euler and BDF2). A coarser sheet can still be cut: at 16x2x16 and
// 32x2x32 a spring ends a frame 4.2 and 3.3 mm inside under backward Euler, as data/scenes/README.md says.
TEST(EdgeContact, ImplicitSheetDrapedOverAKnifeEdgeKeepsEverySpringOut)
{
    const KnifeOutcome with = dropOnKnife(true, 48, IntegratorKind::ImplicitEuler);
    EXPECT_GT(with.touches, 0u);
    EXPECT_LE(with.deepestSpring, 0.01 * with.spacing);
    EXPECT_LE(with.deepestTriangle, 0.01 * with.spacing);
    EXPECT_LT(with.lowestMass, -0.2);
    std::cout << "implicit 48x2x48: deepest spring / triangle inside the knife " << with.deepestSpring << " / "
              << with.deepestTriangle << " m (1% of the spacing: " << 0.01 * with.spacing << " m)\n";
}
