// Bullet's dimensionless kLST against MaSSE's spring constants: the one-link formula, checked on one link, and the
// measured calibration of the Table 1 sheet clamped on two edges.

#include "support/ContactRig.h"
#include "support/TestSystems.h"

#include "bridge/StiffnessCalibration.h"

#include <gtest/gtest.h>

#include <cstdio>

using namespace masse;
using namespace masse::bridge;
using namespace masse::test;

namespace
{
/// The Table 1 sheet of 8 x 2 x 8 masses, clamped on its two edges across x, without air damping (the calibration
/// settles with its own).
MassSpringSystem clampedTableSheet()
{
    const Lattice lattice = buildLattice(LatticeSpec{});
    MassSpringSystem sheet = makeSheet(lattice, SheetParams{});
    clampOnTwoEdges(sheet, lattice);
    return sheet;
}
} // namespace

// Table 1 planar spring (9.2 g/mm = 90.22 N/m) between two free 1 g masses (mu = 0.5 g) at h = 0.03 s:
// k h^2 / mu = 162.40, so kLST = 1 - 1/163.40 = 0.99388 with one pass and 1 - 163.40^(-1/4) = 0.72030 with four.
TEST(StiffnessCalibration, OneLinkFormulaValues)
{
    const Real k = 9.2 * standardGravity;
    EXPECT_NEAR(pbdLinearStiffness(k, 0.0005, 0.03, 1), 0.99388, 1e-5);
    EXPECT_NEAR(pbdLinearStiffness(k, 0.0005, 0.03, 4), 0.72030, 1e-5);
    for (int n : {1, 4, 10})
    {
        const Real kLST = pbdLinearStiffness(k, 0.0005, 0.003, n);
        EXPECT_NEAR(pbdEquivalentStiffness(kLST, 0.0005, 0.003, n), k, 1e-9 * k) << n;
    }
}

// The formula's derivation checked in Bullet itself: a 1 g mass hanging from a pinned one by a single link of
// kLST = pbdLinearStiffness(90.2 N/m, 1 g, h, n) stretches m g / k = 0.1087 mm at rest, within 0.5% (measured:
// 0.2%), for 1, 4 and 10 passes at h = 3 ms and 1 ms. At h = 30 ms the derivation's first-order step fails: gravity
// moves the mass 8.8 mm per step, 9% of the link, and Bullet's projection, nonlinear in the length, overshoots (the
// link rests 0%, 88% and 94% as stretched as the spring for 1, 4, 10 passes).
TEST(StiffnessCalibration, OneLinkStretchesLikeItsSpring)
{
    const Real k = 9.2 * standardGravity;
    MassSpringSystem link = makeChain(2, 0.001, k, 0.1);
    link.forces.gravity = Vec3(0, -standardGravity, 0);
    link.particles.position[1] = Vec3(0, -0.1, 0); // hanging straight down at its rest length
    link.particles.setPinned(0, true);
    const Real expected = 0.001 * standardGravity / k;
    for (int substeps : {10, 30})
    {
        for (int n : {1, 4, 10})
        {
            SoftBodyTwinSettings settings;
            settings.substeps = substeps;
            settings.piterations = n;
            const StaticSag sag = twinStaticSag(link, paperTimeStep, settings);
            EXPECT_TRUE(sag.settled);
            EXPECT_NEAR(sag.sag, expected, 0.005 * expected) << substeps << " substeps, " << n << " passes";
        }
    }
}

// The Table 1 sheet clamped on two edges sags 28.5 mm in MaSSE. Measured on this build (printed):
//   h = 3 ms (10 substeps), 4 passes: the uniform kLST that matches is 0.270 (the formula gives 0.214 planar and
//     0.169 inter-layer, with which the twin sags 63% more); found to 0.1% of the sag.
//   h = 1 ms (30 substeps), 1 pass: k h^2 / mu = 0.18 and the formula's twin sags within 10% of MaSSE (7.4%).
//   h = 30 ms (the paper's step), 4 passes: even rigid links (kLST = 1) sag 6.8 times as much: unreachable.
TEST(StiffnessCalibration, TableSheetClampedOnTwoEdges)
{
    const MassSpringSystem sheet = clampedTableSheet();
    SoftBodyTwinSettings settings;
    settings.substeps = 10;
    settings.piterations = 4;
    const StiffnessCalibration fine = calibrateLinearStiffness(sheet, paperTimeStep, settings);
    const StaticSag formula = twinStaticSag(sheet, paperTimeStep, settings);
    std::printf("h 3 ms, 4 passes: MaSSE sag %.5f m, calibrated kLST %.4f (twin sag %.5f m, %d runs); "
                "formula twin sag %.5f m (%+.1f%%)\n",
                fine.masse.sag, fine.kLST, fine.bullet.sag, fine.evaluations, formula.sag,
                100 * (formula.sag / fine.masse.sag - 1));
    EXPECT_NEAR(fine.masse.sag, 0.0285, 0.0005);
    EXPECT_TRUE(fine.masse.settled && fine.bullet.settled && fine.reachable);
    EXPECT_NEAR(fine.bullet.sag, fine.masse.sag, 1e-3 * fine.masse.sag);
    EXPECT_NEAR(fine.kLST, 0.270, 0.01);
    EXPECT_GT(formula.sag, 1.3 * fine.masse.sag); // the one-link formula is too soft at this load (k h^2/mu = 1.6)

    SoftBodyTwinSettings finest;
    finest.substeps = 30;
    finest.piterations = 1;
    const StaticSag near = twinStaticSag(sheet, paperTimeStep, finest);
    std::printf("h 1 ms, 1 pass: formula twin sag %.5f m (%+.1f%%)\n", near.sag, 100 * (near.sag / fine.masse.sag - 1));
    EXPECT_NEAR(near.sag, fine.masse.sag, 0.10 * fine.masse.sag);

    SoftBodyTwinSettings paper;
    paper.piterations = 4;
    const StiffnessCalibration coarse = calibrateLinearStiffness(sheet, paperTimeStep, paper);
    std::printf("h 30 ms, 4 passes: reachable %d, rigid-link sag %.5f m (%.1f times MaSSE's)\n", coarse.reachable,
                coarse.bullet.sag, coarse.bullet.sag / coarse.masse.sag);
    EXPECT_FALSE(coarse.reachable);
    EXPECT_EQ(coarse.kLST, 1.0);
    EXPECT_GT(coarse.bullet.sag, 5 * coarse.masse.sag);
}
