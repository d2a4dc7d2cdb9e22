// Local sheet thickness h = h0 A0 / A: partition of the area, exact thinning under uniform stretch, volume of the
// thickness field under non-uniform deformation, and where the sheet is thinnest.

#include "core/material/Thickness.h"
#include "core/lattice/Lattice.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

using namespace masse;

namespace
{
const Structure structures[] = {Structure::TRiMM, Structure::SLaMM, Structure::SaMM};

Lattice sheetLattice(Structure structure, int n)
{
    LatticeSpec spec;
    spec.structure = structure;
    spec.countX = n;
    spec.countZ = n;
    return buildLattice(spec);
}

/// A forming-like deformation of the sheet (y up, sheet in x-z): drawn down into a dome of depth D = 0.3 m and
/// radius R = 0.5 m about the middle, y -= D exp(-2 r^2 / R^2), and pulled unevenly wider along x, x += a (x - x0)^2
/// with a = 0.4 /m. `stretch` receives, per mass, the exact local area stretch J = |t1 x t2| of the mapping
/// (x, z) -> (x + a (x - x0)^2, y - bump, z), with t1 = (1 + 2 a (x - x0), dy/dx, 0) and t2 = (0, dy/dz, 1).
std::vector<Vec3> formed(const Lattice& lattice, std::vector<Real>& stretch)
{
    const LatticeSpec& spec = lattice.spec;
    const Vec3 centre = 0.5 * (spec.minCorner + spec.maxCorner);
    const Real radius = 0.5;
    const Real depth = 0.3;
    const Real a = 0.4;
    std::vector<Vec3> x = lattice.position;
    stretch.resize(x.size());
    for (std::size_t i = 0; i < x.size(); ++i)
    {
        const Vec3 rest = lattice.position[i];
        const Real dx = rest.x() - centre.x();
        const Real dz = rest.z() - centre.z();
        const Real bump = depth * std::exp(-2 * (dx * dx + dz * dz) / (radius * radius));
        const Real along = rest.x() - spec.minCorner.x();
        x[i].y() -= bump;
        x[i].x() += a * along * along;
        const Vec3 t1(1 + 2 * a * along, 4 * bump * dx / (radius * radius), 0);
        const Vec3 t2(0, 4 * bump * dz / (radius * radius), 1);
        stretch[i] = t1.cross(t2).norm();
    }
    return x;
}

bool onLayerEdge(const Lattice& lattice, std::size_t i)
{
    const LatticeCoord c = lattice.coord[i];
    return c.row == 0 || c.column == 0 || c.row + 1 == lattice.layerCountZ(c.layer) ||
           c.column + 1 == lattice.layerCountX(c.layer);
}

/// Largest relative error of h against h0 / J over the masses off the layers' edges.
Real worstThicknessError(Structure structure, int n)
{
    const Lattice lattice = sheetLattice(structure, n);
    SheetThickness thickness(lattice, 0.002);
    std::vector<Real> stretch;
    thickness.update(formed(lattice, stretch));
    Real worst = 0;
    for (std::size_t i = 0; i < lattice.massCount(); ++i)
    {
        if (!onLayerEdge(lattice, i))
        {
            worst = std::max(worst, std::abs(thickness.thickness()[i] * stretch[i] / 0.002 - 1));
        }
    }
    return worst;
}
} // namespace

// At rest every mass has h0, and the shares of the bottom layer add up to its cells' area:
// (N-1)^2 hx hz for both families (TRiMM: 2 triangles of hx hz / 2 per row and column).
TEST(Thickness, RestSheetHasInitialThicknessAndSharesPartitionTheArea)
{
    for (Structure structure : structures)
    {
        const Lattice lattice = sheetLattice(structure, 9);
        const SheetThickness thickness(lattice, 0.002);
        Real area = 0;
        for (std::size_t i = 0; i < lattice.massCount(); ++i)
        {
            EXPECT_NEAR(thickness.thickness()[i], 0.002, 1e-15);
            if (lattice.coord[i].layer == 0)
            {
                area += thickness.area()[i];
                EXPECT_NEAR(thickness.normal()[i].y(), 1.0, 1e-12);
            }
        }
        const Real cells = 8.0 * 8.0 * lattice.spacingX * lattice.spacingZ;
        EXPECT_NEAR(area, cells, 1e-12 * cells) << structureName(structure);
        EXPECT_NEAR(thickness.restVolume(), 0.002 * cells, 1e-12 * cells);
    }
}

// Stretching the whole sheet by sx along x and sz along z multiplies every area by sx sz, so every mass of every
// layer thins to h0 / (sx sz) exactly (to rounding).
TEST(Thickness, UniformStretchThinsEveryMassByTheAreaRatio)
{
    for (Structure structure : structures)
    {
        const Lattice lattice = sheetLattice(structure, 7);
        SheetThickness thickness(lattice, 0.003);
        std::vector<Vec3> x = lattice.position;
        for (Vec3& p : x)
        {
            p.x() *= 1.5;
            p.z() *= 1.2;
        }
        thickness.update(x);
        for (std::size_t i = 0; i < x.size(); ++i)
        {
            if (thickness.restArea()[i] > 0)
            {
                EXPECT_NEAR(thickness.thickness()[i], 0.003 / 1.8, 1e-12) << structureName(structure) << " " << i;
            }
        }
    }
}

// Total volume while the sheet is drawn into a dome and stretched unevenly (local area growth up to 80%, the
// thinnest spot at 55% of h0): sum h_i A_i stays h0 A0 (within 0.5%; it is exact to rounding because the shares
// partition the surface). The areas are the deformed surface's: their sum matches the integral of the exact area
// stretch J over the rest sheet (quadrature with the rest shares, sum J_i A0_i) within 0.5%.
TEST(Thickness, VolumeIsConservedWhileTheSheetIsDeformed)
{
    for (Structure structure : structures)
    {
        const Lattice lattice = sheetLattice(structure, 16);
        SheetThickness thickness(lattice, 0.002);
        std::vector<Real> stretch;
        thickness.update(formed(lattice, stretch));
        const Real rest = thickness.restVolume();
        EXPECT_NEAR(thickness.volume(), rest, 0.005 * rest) << structureName(structure);
        Real area = 0;
        Real expectedArea = 0;
        for (std::size_t i = 0; i < lattice.massCount(); ++i)
        {
            if (lattice.coord[i].layer == 0)
            {
                area += thickness.area()[i];
                expectedArea += stretch[i] * thickness.restArea()[i];
            }
        }
        EXPECT_NEAR(area, expectedArea, 0.005 * expectedArea) << structureName(structure);
        EXPECT_LT(thickness.minimumThickness(), 0.6 * 0.002);
    }
}

// Each mass's thickness follows the continuum h0 / J of the deformation: within 2% at every mass off the edges of a
// 16 x 16 sheet, with an error falling as the spacing squared (halving the spacing, 12 to 24 masses a side, divides
// it by more than 3).
TEST(Thickness, ThicknessFollowsTheLocalAreaStretch)
{
    for (Structure structure : structures)
    {
        EXPECT_LT(worstThicknessError(structure, 16), 0.02) << structureName(structure);
        EXPECT_GT(worstThicknessError(structure, 12) / worstThicknessError(structure, 24), 3.0)
            << structureName(structure);
    }
}

// The thinnest spot is where the sheet is stretched most: a narrow bump pulled out of the plane at one mass.
TEST(Thickness, MinimumThicknessIsFoundWhereTheSheetIsPulled)
{
    for (Structure structure : structures)
    {
        const Lattice lattice = sheetLattice(structure, 12);
        SheetThickness thickness(lattice, 0.002);
        const Index pulled = lattice.index(0, 4, 7);
        std::vector<Vec3> x = lattice.position;
        x[pulled].y() -= 0.2;
        thickness.update(x);
        EXPECT_EQ(thickness.thinnestMass(), pulled) << structureName(structure);
        EXPECT_LT(thickness.minimumThickness(), 0.002);
        EXPECT_NEAR(thickness.minimumThickness(), thickness.thickness()[pulled], 0.0);
    }
}

// A 2x2x2 TRiMM sheet's top layer is a single mass over one triangle: it belongs to no cell of its own layer. It is
// given one cell's area (spacingX * spacingZ) and keeps h0 however the sheet moves, so nothing downstream divides by
// a zero area.
TEST(Thickness, LoneTopMassGetsOneCellsAreaAndKeepsItsThickness)
{
    const Lattice lattice = sheetLattice(Structure::TRiMM, 2);
    ASSERT_EQ(lattice.layerCountX(1) * lattice.layerCountZ(1), 1);
    SheetThickness thickness(lattice, 0.002);
    const Index lone = lattice.layerStart[1];
    EXPECT_EQ(thickness.restArea()[lone], lattice.spacingX * lattice.spacingZ);
    std::vector<Vec3> x = lattice.position;
    for (Vec3& p : x)
    {
        p *= 2.0;
    }
    thickness.update(x);
    EXPECT_EQ(thickness.area()[lone], lattice.spacingX * lattice.spacingZ);
    EXPECT_EQ(thickness.thickness()[lone], 0.002);
    EXPECT_NEAR(thickness.thickness()[0], 0.0005, 1e-15);
}
