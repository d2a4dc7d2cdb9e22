// What the renderer draws, without a GL context: the sheet as one closed surface, its colours (scalar, missing
// scalar, the paper's), the heaters, and the pick spring as a coil from the mass to the cursor's point.

#include "viewer/SceneGeometry.h"
#include "viewer/SceneSnapshot.h"
#include "viewer/ViewerSession.h"

#include "bridge/SelfContactTree.h"
#include "core/contact/SelfContact.h"
#include "core/material/HeatSources.h"
#include "scene/SceneFile.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <tuple>

namespace masse::viewer
{
namespace
{
scene::SceneSpec shippedScene(const std::string& name)
{
    return scene::loadScene(std::string(MASSE_SOURCE_DIR) + "/data/scenes/" + name);
}

Vec3 positionOf(const GeometryVertex& v)
{
    return Vec3(v.position[0], v.position[1], v.position[2]);
}

bool hasColour(const GeometryVertex& v, const Rgb& c)
{
    return v.colour[0] == c.r && v.colour[1] == c.g && v.colour[2] == c.b;
}
} // namespace

class SheetSurface : public ::testing::TestWithParam<std::tuple<Structure, int, int>>
{
};

// A closed, consistently wound surface: every edge is used exactly once in each direction (two triangles, wound
// against each other), and its signed volume is positive (the windings face outward). Two open surfaces a layer
// spacing apart fail both: their rims' edges are used once only. The same holds of the coarse surfaces drawn for a
// sheet whose masses lie under a couple of pixels apart (stride 2 and 4).
TEST_P(SheetSurface, IsOneClosedSurfaceWoundOutward)
{
    const auto [structure, layers, stride] = GetParam();
    LatticeSpec spec;
    spec.structure = structure;
    spec.countX = 10;
    spec.countZ = 7;
    spec.layers = layers;
    spec.minCorner = Vec3(0, 0, 0);
    spec.maxCorner = Vec3(0.9, 0.03 * (layers - 1), 0.6);
    const Lattice lattice = buildLattice(spec);
    const std::vector<std::uint32_t> triangles =
        stride == 1 ? sheetSurfaceTriangles(lattice) : coarseSurfaceTriangles(lattice, stride);
    ASSERT_EQ(triangles.size() % 3, 0u);

    std::map<std::pair<std::uint32_t, std::uint32_t>, int> directedEdges;
    Real volume = 0;
    for (std::size_t t = 0; t < triangles.size(); t += 3)
    {
        const std::uint32_t a = triangles[t];
        const std::uint32_t b = triangles[t + 1];
        const std::uint32_t c = triangles[t + 2];
        ++directedEdges[{a, b}];
        ++directedEdges[{b, c}];
        ++directedEdges[{c, a}];
        const Vec3& pa = lattice.position[a];
        const Vec3& pb = lattice.position[b];
        const Vec3& pc = lattice.position[c];
        volume += pa.dot(pb.cross(pc)) / 6;
        EXPECT_GT((pb - pa).cross(pc - pa).norm(), 1e-9) << "a degenerate triangle " << a << " " << b << " " << c;
    }
    int unmatched = 0;
    for (const auto& [edge, count] : directedEdges)
    {
        EXPECT_EQ(count, 1) << "edge " << edge.first << "-" << edge.second << " wound the same way twice";
        const auto reverse = directedEdges.find({edge.second, edge.first});
        unmatched += reverse == directedEdges.end() ? 1 : 0;
    }
    EXPECT_EQ(unmatched, 0) << "edges on an open rim";
    // The sheet tapers by half a spacing a side and layer: its volume is below the bottom layer's footprint times
    // the thickness, and well above a quarter of that.
    const Real thickness = 0.03 * (layers - 1);
    EXPECT_GT(volume, 0.25 * 0.9 * 0.6 * thickness) << "wound inward, or not closed";
    EXPECT_LT(volume, 0.9 * 0.6 * thickness * 1.0001);

    // No inner layer's face: every mass of a middle layer used is on its rim.
    for (std::uint32_t mass : triangles)
    {
        const LatticeCoord& coord = lattice.coord[mass];
        if (coord.layer > 0 && coord.layer + 1 < layers)
        {
            const bool rim = coord.row == 0 || coord.column == 0 || coord.row == lattice.layerCountZ(coord.layer) - 1 ||
                             coord.column == lattice.layerCountX(coord.layer) - 1;
            EXPECT_TRUE(rim) << "mass " << mass << " inside layer " << coord.layer;
        }
    }
    if (stride > 1)
    {
        EXPECT_LT(triangles.size(), sheetSurfaceTriangles(lattice).size() / 2) << "coarse means fewer triangles";
    }
}

INSTANTIATE_TEST_SUITE_P(StructuresAndLayers, SheetSurface,
                         ::testing::Combine(::testing::Values(Structure::SaMM, Structure::SLaMM, Structure::TRiMM),
                                            ::testing::Values(2, 3), ::testing::Values(1, 2, 4)));

TEST(SheetSurfaceSingleLayer, IsTheLayersOwnTriangles)
{
    LatticeSpec spec;
    spec.structure = Structure::Square2D;
    spec.layers = 1;
    spec.countX = 4;
    spec.countZ = 3;
    const Lattice lattice = buildLattice(spec);
    EXPECT_EQ(sheetSurfaceTriangles(lattice).size(), std::size_t(3 * 2 * 3 * 2));
}

TEST(SheetArrays, AScalarTheSceneLacksIsGreyWithoutARangeAndOneItHasIsMappedOverItsRange)
{
    ViewerSession session(shippedScene("paper-drop.json"));
    const MassScalarRegistry scalars = standardMassScalars();
    SceneSnapshot snapshot;
    DrawSettings settings;
    settings.mode = DrawMode::Scalar;
    settings.scalar = "temperature";
    captureSnapshot(session, scalars, "temperature", nullptr, snapshot);
    SheetArrays arrays;
    buildSheetArrays(snapshot, settings, arrays);
    EXPECT_FALSE(arrays.scalarRange);
    ASSERT_EQ(arrays.colours.size(), 3 * snapshot.positions.size());
    EXPECT_EQ(arrays.colours[0], palette::missingScalar.r);
    EXPECT_EQ(arrays.normals.size(), 3 * snapshot.positions.size()) << "a surface mode needs normals";

    session.advanceSteps(5);
    settings.scalar = "speed";
    captureSnapshot(session, scalars, "speed", &snapshot, snapshot);
    buildSheetArrays(snapshot, settings, arrays);
    ASSERT_TRUE(arrays.scalarRange);
    EXPECT_GT(arrays.scalarRange->high, 0.5f) << "5 steps of free fall: 1.5 m/s at the start of the drop";
    EXPECT_LT(arrays.scalarRange->low, arrays.scalarRange->high);

    settings.mode = DrawMode::MassesAndSprings;
    buildSheetArrays(snapshot, settings, arrays);
    EXPECT_FALSE(arrays.scalarRange);
    EXPECT_TRUE(arrays.normals.empty());
    EXPECT_EQ(arrays.colours[0], palette::mass.r);
    EXPECT_EQ(arrays.colours[1], palette::mass.g);
}

// With contact.self_collision, the masses of every pair touching at the last substep are drawn magenta (over the
// obstacle contact's green): none while the fold over the rod is still open, and once its halves have met, exactly the
// masses of the pairs within the radius (the response leaves a touching pair at the radius; a separate self-contact of
// the same lattice measures them), and only in the fold's scene.
TEST(SheetArrays, MassesTouchingTheSheetItselfAreMagenta)
{
    ViewerSession session(shippedScene("fold-over-rod.json"));
    const MassScalarRegistry scalars = standardMassScalars();
    SceneSnapshot snapshot;
    DrawSettings settings;
    settings.mode = DrawMode::MassesAndSprings;
    SheetArrays arrays;
    const auto magenta = [&]
    {
        buildSheetArrays(snapshot, settings, arrays);
        std::vector<Index> masses;
        for (std::size_t i = 0; i < snapshot.positions.size(); ++i)
        {
            const float* c = &arrays.colours[3 * i];
            if (c[0] == palette::massInSelfContact.r && c[1] == palette::massInSelfContact.g &&
                c[2] == palette::massInSelfContact.b)
            {
                masses.push_back(Index(i));
            }
        }
        return masses;
    };
    session.advanceSteps(5); // 0.15 s: falling, the halves far apart
    captureSnapshot(session, scalars, "", nullptr, snapshot);
    EXPECT_TRUE(magenta().empty());
    EXPECT_EQ(snapshot.selfTouchingCount, 0u);

    session.advanceSteps(20); // 0.75 s: the halves met at 0.41 s
    captureSnapshot(session, scalars, "", &snapshot, snapshot);
    const std::vector<Index> touching = magenta();
    ASSERT_GT(session.scene().selfContact()->report().lastSubstep, 0u) << "the halves have not met";
    EXPECT_FALSE(touching.empty());
    EXPECT_EQ(touching.size(), snapshot.selfTouchingCount);

    scene::Scene& scene = session.scene();
    bridge::SelfContactTree tree;
    SelfContactSettings measure;
    measure.radius = scene.spec().contact.radius;
    SelfContact surface(scene.lattice(), tree, measure);
    std::vector<SelfContactPair> pairs;
    surface.pairsWithin(scene.system().particles.position, 1.001 * measure.radius, pairs);
    std::vector<Index> expected;
    for (const SelfContactPair& pair : pairs)
    {
        expected.push_back(pair.vertex);
        for (const Index i : surface.triangles()[pair.triangle])
        {
            expected.push_back(i);
        }
    }
    std::sort(expected.begin(), expected.end());
    expected.erase(std::unique(expected.begin(), expected.end()), expected.end());
    for (const Index i : touching)
    {
        EXPECT_TRUE(std::binary_search(expected.begin(), expected.end(), i)) << "mass " << i << " is not touching";
    }

    ViewerSession drop(shippedScene("paper-drop.json"));
    drop.advanceSteps(25);
    captureSnapshot(drop, scalars, "", nullptr, snapshot);
    EXPECT_TRUE(magenta().empty()) << "no self-contact in a scene without it";
}

// The drape-forming scene's panel: drawn where the scene puts it, glowing while on, dark once switched off.
TEST(EnvironmentGeometry, HeatersAreDrawnAtTheirPanelAndShowWhetherTheyAreOn)
{
    ViewerSession session(shippedScene("drape-forming.json"));
    const MassScalarRegistry scalars = standardMassScalars();
    SceneSnapshot snapshot;
    captureSnapshot(session, scalars, "", nullptr, snapshot);
    const RadiantHeater& heater = snapshot.spec->heat.settings.heaters.at(0);
    const std::array<Vec3, 4> corners = heaterCorners(heater);

    // The heating elements: lines of the heater's colour on the panel's plane, within its outline.
    auto elementEnds = [&](const EnvironmentGeometry& geometry, const Rgb& colour)
    {
        int n = 0;
        const Vec3 normal = heater.normal.normalized();
        for (const GeometryVertex& v : geometry.lines)
        {
            const Vec3 offset = positionOf(v) - heater.centre;
            if (!hasColour(v, colour) || std::abs(offset.dot(normal)) > 1e-6)
            {
                continue; // a ray, or something else
            }
            ++n;
            EXPECT_LE(std::abs(offset.x()), heater.width / 2 + 1e-6);
            EXPECT_LE(std::abs(offset.z()), heater.length / 2 + 1e-6);
        }
        return n;
    };
    EXPECT_NEAR((corners[0] - heater.centre).norm(), std::hypot(heater.width, heater.length) / 2, 1e-9);
    const EnvironmentGeometry on = buildEnvironment(snapshot, true);
    EXPECT_GE(elementEnds(on, heaterColour(true)), 2 * 5) << "several glowing elements";
    EXPECT_EQ(elementEnds(on, heaterColour(false)), 0);

    session.scene().setHeater(0, false);
    captureSnapshot(session, scalars, "", &snapshot, snapshot);
    const EnvironmentGeometry off = buildEnvironment(snapshot, true);
    EXPECT_EQ(elementEnds(off, heaterColour(false)) + 5, elementEnds(on, heaterColour(true)))
        << "the same elements, and the five rays that start on the panel while it is on";
    EXPECT_EQ(elementEnds(off, heaterColour(true)), 0);
    EXPECT_LT(off.lines.size(), on.lines.size()) << "the rays go with the heat";

    // A scene without heat draws no heater.
    ViewerSession drop(shippedScene("paper-drop.json"));
    captureSnapshot(drop, scalars, "", nullptr, snapshot);
    const EnvironmentGeometry none = buildEnvironment(snapshot, true);
    for (const GeometryVertex& v : none.lines)
    {
        EXPECT_FALSE(hasColour(v, heaterColour(true)) || hasColour(v, heaterColour(false)));
    }
}

TEST(SpringCoil, RunsFromTheMassToTheTargetWithinItsRadius)
{
    const Vec3 from(0.1, 0.2, 0.3);
    const Vec3 to(0.4, 0.6, 0.3);
    const Real radius = 0.02;
    const std::vector<Vec3> coil = springCoil(from, to, radius, 8);
    ASSERT_GT(coil.size(), 8u * 4);
    EXPECT_EQ(coil.front(), from);
    EXPECT_EQ(coil.back(), to);
    const Vec3 axis = (to - from).normalized();
    Real widest = 0;
    for (const Vec3& p : coil)
    {
        const Vec3 offset = p - from;
        const Real along = offset.dot(axis);
        EXPECT_GE(along, -1e-12);
        EXPECT_LE(along, (to - from).norm() + 1e-12);
        widest = std::max(widest, (offset - along * axis).norm());
    }
    EXPECT_LE(widest, radius + 1e-12);
    EXPECT_GT(widest, 0.9 * radius) << "a coil, not a straight line";
    EXPECT_EQ(springCoil(from, from, radius, 8).size(), 2u);
}

TEST(OverlayGeometry, ThePickSpringRunsFromThePickedMassToTheCursorsPoint)
{
    ViewerSession session(shippedScene("paper-drop.json"));
    SceneSnapshot snapshot;
    captureSnapshot(session, standardMassScalars(), "", nullptr, snapshot);
    const Index mass = snapshot.positions.size() / 2;
    const Vec3 target = snapshot.positions[mass] + Vec3(0, 0.2, 0);
    const OverlayGeometry overlays = buildOverlays(snapshot, std::pair<Index, Vec3>(mass, target));
    ASSERT_GE(overlays.lines.size(), 2u * 40);
    for (const GeometryVertex& v : overlays.lines)
    {
        EXPECT_TRUE(hasColour(v, palette::pick));
    }
    EXPECT_LT((positionOf(overlays.lines.front()) - snapshot.positions[mass]).norm(), 1e-6);
    EXPECT_LT((positionOf(overlays.lines.back()) - target).norm(), 1e-6);
    ASSERT_EQ(overlays.points.size(), 2u) << "the picked mass and the cursor's point";

    // Without a pick nothing is drawn; the session's own pick (from the snapshot) is drawn the same way.
    EXPECT_TRUE(buildOverlays(snapshot, std::nullopt).lines.empty());
    session.beginPick(mass, target);
    captureSnapshot(session, standardMassScalars(), "", &snapshot, snapshot);
    EXPECT_EQ(buildOverlays(snapshot, std::nullopt).lines.size(), overlays.lines.size());
}
} // namespace masse::viewer

namespace masse::viewer
{
// Masses under a couple of pixels apart are thinned by powers of two, every layer alike, corners kept.
TEST(MassThinning, KeepsEveryStridethRowAndColumnOfEachLayer)
{
    LatticeSpec spec;
    spec.structure = Structure::TRiMM;
    spec.countX = 9;
    spec.countZ = 7;
    spec.layers = 2;
    const Lattice lattice = buildLattice(spec);
    const std::vector<std::uint32_t> half = massesAtStride(lattice, 2);
    // Layer 0: 5 x 4 of its 9 x 7; layer 1: 4 x 3 of its 8 x 6.
    EXPECT_EQ(half.size(), std::size_t(5 * 4 + 4 * 3));
    EXPECT_EQ(half.front(), std::uint32_t(lattice.index(0, 0, 0)));
    for (std::uint32_t mass : half)
    {
        EXPECT_EQ(lattice.coord[mass].row % 2, 0);
        EXPECT_EQ(lattice.coord[mass].column % 2, 0);
    }
    EXPECT_TRUE(std::is_sorted(half.begin(), half.end()));
    EXPECT_EQ(massesAtStride(lattice, 1).size(), lattice.massCount());

    EXPECT_EQ(massStride(10), 1) << "far enough apart: every mass";
    EXPECT_EQ(massStride(minMassSpacingPixels), 1);
    EXPECT_EQ(massStride(2), 2);
    EXPECT_EQ(massStride(1), 4);
    EXPECT_EQ(massStride(0.7), 4);
    EXPECT_EQ(massStride(0.01), maxMassStride) << "never coarser than the coarsest level kept";
    for (Real pixels : {0.2, 0.5, 0.9, 1.3, 2.0})
    {
        const int stride = massStride(pixels);
        EXPECT_GE(pixels * stride, minMassSpacingPixels);
        EXPECT_LT(pixels * stride / 2, minMassSpacingPixels) << "the finest stride that is far enough apart";
    }
}
} // namespace masse::viewer
