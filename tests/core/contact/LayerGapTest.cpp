// The layer floor (core/contact/LayerGap.h): an upper-layer mass pushed onto or through the cell of masses beneath it
// is put back at its floor, its approach stopped, momentum kept; a mass held by an obstacle does not give way, and one
// on the mould through a cell partly on it moves back alone; a mirror-symmetric push is corrected mirror-symmetrically;
// the floor falls over a warped cell, a correction moves a mass at most eight floor heights, after the implicit solve
// the velocity takes no more of it than the solve closed, and after the projection no correction puts a mass's centre
// behind the mould.

#include "support/FlatMould.h"
#include "support/TestSystems.h"

#include "core/StepContext.h"
#include "core/contact/ContactSolver.h"
#include "core/contact/LayerGap.h"
#include "core/lattice/SpringTopology.h"

#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace masse;

namespace
{
/// The masses of the layer below joined to upper mass i by an inter-layer spring.
std::vector<Index> cellOf(const Lattice& lattice, Index i)
{
    std::vector<Index> cell;
    for (const SpringEnds& s : lattice.springs.ends())
    {
        if (s.a == i && lattice.coord[s.b].layer + 1 == lattice.coord[i].layer)
        {
            cell.push_back(s.b);
        }
        if (s.b == i && lattice.coord[s.a].layer + 1 == lattice.coord[i].layer)
        {
            cell.push_back(s.a);
        }
    }
    return cell;
}

Vec3 momentum(const Particles& p)
{
    Vec3 sum = Vec3::Zero();
    for (std::size_t i = 0; i < p.size(); ++i)
    {
        sum += p.mass[i] * p.velocity[i];
    }
    return sum;
}

Vec3 massMoment(const Particles& p)
{
    Vec3 sum = Vec3::Zero();
    for (std::size_t i = 0; i < p.size(); ++i)
    {
        sum += p.mass[i] * p.position[i];
    }
    return sum;
}

struct PushedSheet
{
    Lattice lattice;
    MassSpringSystem sheet;
    Index upper = 0;
    Real restHeight = 0;
};

/// A flat 5 x 2 x 5 sheet of the given structure whose middle upper mass is pushed `depth` rest heights below the
/// rest position, moving toward its cell at 1 m/s.
PushedSheet pushedSheet(Structure structure, Real depth)
{
    LatticeSpec spec;
    spec.structure = structure;
    spec.countX = 5;
    spec.countZ = 5;
    spec.minCorner = Vec3(-0.02, 0, -0.02);
    spec.maxCorner = Vec3(0.02, 0.004, 0.02);
    PushedSheet s;
    s.lattice = buildLattice(spec);
    s.sheet = makeSheet(s.lattice, SheetParams{});
    s.upper = s.lattice.index(1, 1, 1);
    s.restHeight = spec.maxCorner.y() - spec.minCorner.y();
    s.sheet.particles.position[s.upper].y() -= depth * s.restHeight;
    s.sheet.particles.velocity[s.upper] = Vec3(0, -1, 0);
    return s;
}

Real heightOverCell(const PushedSheet& s)
{
    Real cellY = 0;
    const std::vector<Index> cell = cellOf(s.lattice, s.upper);
    for (Index j : cell)
    {
        cellY += s.sheet.particles.position[j].y();
    }
    return s.sheet.particles.position[s.upper].y() - cellY / Real(cell.size());
}
} // namespace

// A mass pushed through its cell (1.5 rest heights down: half a height below the cell) comes back to the rest height
// over it (the floor of a sheet without a thickness field), to rounding; the cell takes its share of the move, so the
// centre of mass and the momentum stay where they were; the approach along the normal is gone.
TEST(LayerGap, PutsAMassPushedThroughItsCellBackAtItsFloor)
{
    for (Structure structure : {Structure::TRiMM, Structure::SaMM, Structure::SLaMM})
    {
        PushedSheet s = pushedSheet(structure, 1.5);
        ASSERT_LT(heightOverCell(s), 0);
        const Vec3 moment = massMoment(s.sheet.particles);
        const Vec3 impulse = momentum(s.sheet.particles);
        LayerGap gap(s.lattice);
        StepContext context;
        gap.afterSubstep(s.sheet, context, 0.01, 0.01);
        EXPECT_NEAR(heightOverCell(s), s.restHeight, 1e-12 * s.restHeight) << structureName(structure);
        EXPECT_NEAR((massMoment(s.sheet.particles) - moment).norm(), 0, 1e-15) << structureName(structure);
        EXPECT_NEAR((momentum(s.sheet.particles) - impulse).norm(), 0, 1e-15) << structureName(structure);
        Vec3 cellVelocity = Vec3::Zero();
        const std::vector<Index> cell = cellOf(s.lattice, s.upper);
        for (Index j : cell)
        {
            cellVelocity += s.sheet.particles.velocity[j] / Real(cell.size());
        }
        EXPECT_NEAR(s.sheet.particles.velocity[s.upper].y() - cellVelocity.y(), 0, 1e-12) << structureName(structure);
        EXPECT_EQ(gap.lastCorrected(), 1 + cell.size()) << structureName(structure);
    }
}

// Over a cell held by an obstacle, the upper mass alone moves: the mould does not give way to the layer above it.
// And a mass above its floor is left alone.
TEST(LayerGap, AMassHeldByAnObstacleDoesNotGiveWay)
{
    PushedSheet s = pushedSheet(Structure::TRiMM, 0.9);
    std::vector<int> touching(s.sheet.massCount(), -1);
    const std::vector<Index> cell = cellOf(s.lattice, s.upper);
    std::vector<Vec3> cellBefore;
    for (Index j : cell)
    {
        touching[j] = 0;
        cellBefore.push_back(s.sheet.particles.position[j]);
    }
    LayerGap gap(s.lattice);
    StepContext context;
    context.touchingObstacle = touching;
    gap.afterSubstep(s.sheet, context, 0.01, 0.01);
    EXPECT_NEAR(heightOverCell(s), s.restHeight, 1e-12 * s.restHeight);
    for (std::size_t k = 0; k < cell.size(); ++k)
    {
        EXPECT_EQ(s.sheet.particles.position[cell[k]], cellBefore[k]);
    }
    EXPECT_EQ(gap.lastCorrected(), 1u);

    const std::vector<Vec3> after = s.sheet.particles.position;
    gap.afterSubstep(s.sheet, context, 0.01, 0.02);
    EXPECT_TRUE(test::sameBits(after, s.sheet.particles.position));
    EXPECT_EQ(gap.lastCorrected(), 0u);
}

// An upper mass on the mould that has gone through a cell only partly on it (a cell draped over a rim: one corner on
// the flange, the others free) moves back alone: the free corners stay where they were, where they would otherwise
// take the whole correction, three times the deficit on a lone free corner. Above its cell (not through it) such a
// mass is held like any other, and the free corners take the correction.
TEST(LayerGap, AMassThroughACellPartlyOnTheMouldMovesBackAlone)
{
    for (const Real depth : {1.5, 0.9})
    {
        PushedSheet s = pushedSheet(Structure::TRiMM, depth);
        std::vector<int> touching(s.sheet.massCount(), -1);
        const std::vector<Index> cell = cellOf(s.lattice, s.upper);
        ASSERT_EQ(cell.size(), 3u);
        touching[s.upper] = 0;
        touching[cell[0]] = 0;
        std::vector<Vec3> cellBefore;
        for (Index j : cell)
        {
            cellBefore.push_back(s.sheet.particles.position[j]);
        }
        const Vec3 upperBefore = s.sheet.particles.position[s.upper];
        LayerGap gap(s.lattice);
        StepContext context;
        context.touchingObstacle = touching;
        gap.afterSubstep(s.sheet, context, 0.01, 0.01);
        EXPECT_NEAR(heightOverCell(s), s.restHeight, 1e-12 * s.restHeight) << "depth " << depth;
        if (depth > 1)
        {
            for (std::size_t k = 0; k < cell.size(); ++k)
            {
                EXPECT_EQ(s.sheet.particles.position[cell[k]], cellBefore[k]) << "corner " << k;
            }
            EXPECT_EQ(gap.lastCorrected(), 1u);
        }
        else
        {
            EXPECT_EQ(s.sheet.particles.position[s.upper], upperBefore);
            EXPECT_EQ(s.sheet.particles.position[cell[0]], cellBefore[0]);
            EXPECT_NE(s.sheet.particles.position[cell[1]], cellBefore[1]);
            EXPECT_EQ(gap.lastCorrected(), 2u);
        }
    }
}

// A SaMM sheet of odd counts pressed flat in a mirror-symmetric pattern is corrected mirror-symmetrically: every
// constraint is solved from the same positions, whatever the order of the masses.
TEST(LayerGap, MirrorSymmetricPushIsCorrectedMirrorSymmetrically)
{
    LatticeSpec spec;
    spec.structure = Structure::SaMM;
    spec.countX = 7;
    spec.countZ = 7;
    spec.minCorner = Vec3(-0.03, 0, -0.03);
    spec.maxCorner = Vec3(0.03, 0.004, 0.03);
    const Lattice lattice = buildLattice(spec);
    MassSpringSystem sheet = makeSheet(lattice, SheetParams{});
    Particles& p = sheet.particles;
    for (std::size_t i = 0; i < p.size(); ++i)
    {
        if (lattice.coord[i].layer == 1)
        {
            // Pressed down in a bowl, deepest in the middle: every upper mass goes below its floor by a different
            // amount.
            p.position[i].y() -=
                0.004 * (1.2 - 20 * p.position[i].x() * p.position[i].x() - 30 * p.position[i].z() * p.position[i].z());
        }
    }
    // The bottom layer's outer ring lies on an obstacle: the cells next to it are pressed, and their corrections
    // meet at the corners they share.
    std::vector<int> touching(p.size(), -1);
    for (std::size_t i = 0; i < p.size(); ++i)
    {
        const LatticeCoord& c = lattice.coord[i];
        if (c.layer == 0 && (c.row == 0 || c.column == 0 || c.row == 6 || c.column == 6))
        {
            touching[i] = 0;
        }
    }
    LayerGap gap(lattice);
    StepContext context;
    context.touchingObstacle = touching;
    gap.afterSubstep(sheet, context, 0.01, 0.01);
    ASSERT_GT(gap.lastCorrected(), 20u);
    Real worst = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
    {
        const LatticeCoord& c = lattice.coord[i];
        const int nx = lattice.layerCountX(c.layer);
        const int nz = lattice.layerCountZ(c.layer);
        const Vec3& x = p.position[i];
        const Vec3& acrossX = p.position[lattice.index(c.layer, c.row, nx - 1 - c.column)];
        const Vec3& acrossZ = p.position[lattice.index(c.layer, nz - 1 - c.row, c.column)];
        worst = std::max({worst, std::abs(x.y() - acrossX.y()), std::abs(x.x() + acrossX.x()),
                          std::abs(x.y() - acrossZ.y()), std::abs(x.z() + acrossZ.z())});
    }
    EXPECT_LT(worst, 1e-15);
}

// A cell folded over a mould's rim has no plane to stand over: the floor falls with the cell's warp (the distance
// between its diagonals' midpoints along its normal), to half the rest height at a warp of half of it and to nothing
// at a warp of the rest height or more.
TEST(LayerGap, TheFloorFallsWithItsCellsWarp)
{
    for (const Real warp : {0.5, 1.2})
    {
        PushedSheet s = pushedSheet(Structure::SaMM, 0);
        Particles& p = s.sheet.particles;
        const std::vector<Index> cell = cellOf(s.lattice, s.upper);
        ASSERT_EQ(cell.size(), 4u);
        // Two diagonal corners lifted: the diagonals stay level (the normal stays upright), their midpoints part by
        // the lift, the centroid rises by half of it.
        const Index first = s.lattice.index(0, 1, 1);
        const Index last = s.lattice.index(0, 2, 2);
        p.position[first].y() += warp * s.restHeight;
        p.position[last].y() += warp * s.restHeight;
        // The upper mass a tenth of the rest height over the centroid.
        p.position[s.upper].y() = 0.5 * warp * s.restHeight + 0.1 * s.restHeight;
        p.velocity[s.upper] = Vec3::Zero();
        LayerGap gap(s.lattice);
        StepContext context;
        gap.afterSubstep(s.sheet, context, 0.01, 0.01);
        const Real ratio = gap.heightRatios(p.position)[s.upper];
        if (warp < 1)
        {
            EXPECT_NEAR(ratio, 1 - warp, 1e-12) << "warp " << warp;
        }
        else
        {
            EXPECT_EQ(gap.lastCorrected(), 0u) << "warp " << warp;
            EXPECT_NEAR(ratio, 0.1, 1e-12) << "warp " << warp;
        }
    }
}

// A mass far across its cell (19 rest heights below it) is not thrown back in one substep: its height over the cell
// grows by eight floor heights a substep, and it is over the cell again after three.
TEST(LayerGap, AMassFarAcrossItsCellComesBackEightFloorsASubstep)
{
    PushedSheet s = pushedSheet(Structure::TRiMM, 20);
    LayerGap gap(s.lattice);
    StepContext context;
    const Real before = heightOverCell(s);
    ASSERT_NEAR(before, -19 * s.restHeight, 1e-12);
    gap.afterSubstep(s.sheet, context, 0.01, 0.01);
    EXPECT_NEAR(heightOverCell(s), before + 8 * s.restHeight, 1e-12);
    gap.afterSubstep(s.sheet, context, 0.01, 0.02);
    gap.afterSubstep(s.sheet, context, 0.01, 0.03);
    EXPECT_NEAR(heightOverCell(s), s.restHeight, 1e-12);
}

// After the implicit solve the approach is taken out of the velocity only as far as the solve itself can have closed
// the gap: by deficit / h, as position-based dynamics sets v = (x - x0) / h. The upper mass, 1.5 rest heights (6 mm)
// too low and closing at 1 m/s: a solve of 10 ms closed 10 mm and the velocity keeps closing at 1 - 0.6 = 0.4 m/s;
// a solve of 1 ms closed 1 mm, so most of the deficit is older than the solve, and the approach is only stopped (a
// mass found 8 floors down by a short solve was thrown out at 8 floors per solve). Momentum is kept either way.
TEST(LayerGap, AfterTheSolveTheVelocityTakesNoMoreThanTheSolveClosed)
{
    for (const Real h : {0.01, 0.001})
    {
        PushedSheet s = pushedSheet(Structure::SaMM, 1.5);
        const Vec3 impulse = momentum(s.sheet.particles);
        const std::vector<Index> cell = cellOf(s.lattice, s.upper);
        const auto closing = [&]
        {
            Vec3 cellVelocity = Vec3::Zero();
            for (Index j : cell)
            {
                cellVelocity += s.sheet.particles.velocity[j];
            }
            return -(s.sheet.particles.velocity[s.upper] - cellVelocity / Real(cell.size())).y();
        };
        const Real closingBefore = closing();
        const Real deficit = 1.5 * s.restHeight;
        LayerGap gap(s.lattice);
        StepContext context;
        gap.afterImplicitSolve(s.sheet, context, h, h);
        ASSERT_EQ(gap.lastCorrected(), 5u);
        EXPECT_NEAR(closing(), closingBefore - std::min(closingBefore, deficit / h), 1e-12) << "h " << h;
        EXPECT_NEAR((momentum(s.sheet.particles) - impulse).norm(), 0, 1e-15) << "h " << h;
    }
}

// The floor's correction after the substep comes after the obstacle contact's projection, so nothing else would stop
// it from pushing a lower mass into the mould: an upper mass held by the plug, 1.5 rest heights (6 mm) too low over a
// cell 1 mm above the mould (its spheres'), pushes the whole deficit into the cell, which would end with its centres
// 3 mm behind the mould's surface; the next frame would find them there and take them for a touch from the other
// side. With the contact, each is put back onto the surface and its speed into it taken out. A push that leaves the
// centre in front of the surface is left to the next frame's projection.
TEST(LayerGap, AfterTheProjectionACorrectionPutsNoCentreBehindTheMould)
{
    for (const bool withContact : {false, true})
    {
        PushedSheet s = pushedSheet(Structure::TRiMM, 1.5);
        const std::vector<Index> cell = cellOf(s.lattice, s.upper);
        ContactSettings settings;
        settings.radius = 0.002;
        const Real floorY = s.sheet.particles.position[cell[0]].y() - settings.radius - 0.001;
        test::FlatMould floor(floorY);
        ContactSolver contact(floor, settings);
        StepContext context;
        contact.detect(s.sheet, context, 0, 0.01, false);
        std::vector<int> touching(s.sheet.massCount(), -1);
        touching[s.upper] = 0; // held by the plug
        context.touchingObstacle = touching;
        LayerGap gap(s.lattice);
        if (withContact)
        {
            gap.setContactSolver(&contact);
        }
        gap.afterSubstep(s.sheet, context, 0.01, 0.01);
        for (Index j : cell)
        {
            const Real y = s.sheet.particles.position[j].y();
            if (withContact)
            {
                EXPECT_NEAR(y, floorY + settings.radius, 1e-15) << "mass " << j;
                EXPECT_GE(s.sheet.particles.velocity[j].y(), 0) << "mass " << j;
            }
            else
            {
                EXPECT_NEAR(y, floorY - 0.003, 1e-12) << "mass " << j << ": the set-up no longer pushes it through";
            }
        }
    }
}
