// The lattice-convergence comparison (scene/study/Convergence.h): Richardson's estimate recovers the limit of a
// sequence f(h) = f* + C h^p and its order from three sizes, takes order 1 from two, and does not extrapolate
// differences that do not shrink or shrink too slowly; the sizes asked for are read as the command's flag says.

#include "scene/study/Convergence.h"
#include "core/InputError.h"

#include <gtest/gtest.h>

#include <cmath>
#include <string>

using namespace masse;
using namespace masse::scene;

namespace
{
std::vector<Real> sequence(const std::vector<Real>& cellSizes, Real limit, Real scale, Real order)
{
    std::vector<Real> values;
    for (Real h : cellSizes)
    {
        values.push_back(limit + scale * std::pow(h, order));
    }
    return values;
}
} // namespace

// Three sizes halving the cell, and three whose ratios differ (16, 24, 32 masses along 0.36 m): the order and the
// limit come back to the bisection's and rounding's precision (1e-9), for orders 1, 1.5 and 2 and either sign of C.
TEST(Convergence, RichardsonRecoversTheLimitAndOrderOfAPowerLaw)
{
    for (const std::vector<Real>& cells :
         {std::vector<Real>{0.02, 0.01, 0.005}, std::vector<Real>{0.36 / 15, 0.36 / 23, 0.36 / 31}})
    {
        for (Real order : {1.0, 1.5, 2.0})
        {
            for (Real scale : {-40.0, 25.0})
            {
                const RichardsonEstimate e = richardson(sequence(cells, 0.2, scale, order), cells);
                EXPECT_TRUE(e.extrapolated);
                EXPECT_TRUE(e.orderMeasured);
                EXPECT_NEAR(e.order, order, 1e-9) << "order " << order << " C " << scale;
                EXPECT_NEAR(e.value, 0.2, 1e-9) << "order " << order << " C " << scale;
                EXPECT_NEAR(e.band, std::abs(scale) * std::pow(cells.back(), order), 1e-9);
            }
        }
    }
}

// Two sizes cannot measure the order: 1 is taken, which is exact for a first-order sequence and, for a second-order
// one, over-corrects (the band is larger than the finest run's true error, here 3 times as large for h halved).
TEST(Convergence, TwoSizesTakeOrderOne)
{
    const std::vector<Real> cells{0.02, 0.01};
    const RichardsonEstimate first = richardson(sequence(cells, 0.3, 5, 1), cells);
    EXPECT_FALSE(first.orderMeasured);
    EXPECT_EQ(first.order, 1);
    EXPECT_NEAR(first.value, 0.3, 1e-12);
    const RichardsonEstimate second = richardson(sequence(cells, 0.3, 5, 2), cells);
    const Real trueError = 5 * 0.01 * 0.01;
    EXPECT_NEAR(second.band, 3 * trueError, 1e-12);
}

// Differences that grow, or change sign, are not extrapolated: the estimate is the finest value and the band the last
// difference.
TEST(Convergence, DifferencesThatDoNotShrinkAreNotExtrapolated)
{
    const std::vector<Real> cells{0.02, 0.01, 0.005};
    for (const std::vector<Real>& values : {std::vector<Real>{0.27, 0.24, 0.20}, std::vector<Real>{0.27, 0.22, 0.24}})
    {
        const RichardsonEstimate e = richardson(values, cells);
        EXPECT_FALSE(e.extrapolated);
        EXPECT_EQ(e.value, values.back());
        EXPECT_NEAR(e.band, std::abs(values[2] - values[1]), 1e-15);
    }
}

// Differences that shrink more slowly than order minimumOrder are not extrapolated either: the cup's thinnest wall
// as a sheet that does not strain-harden nor follow its thickness gives (0.2319, 0.2255, 0.2193 h0 at 32, 64 and 128
// masses a side: order 0.04, whose Richardson estimate is -0.09 h0), and a power law of order 0.3. A power law just
// above the bound, order 0.6, is extrapolated to its limit.
TEST(Convergence, DifferencesThatShrinkTooSlowlyAreNotExtrapolated)
{
    const std::vector<Real> cells{0.26 / 31, 0.26 / 63, 0.26 / 127};
    for (const std::vector<Real>& values : {std::vector<Real>{0.2319, 0.2255, 0.2193}, sequence(cells, 0.2, 0.5, 0.3)})
    {
        const RichardsonEstimate e = richardson(values, cells);
        EXPECT_TRUE(e.orderMeasured);
        EXPECT_GT(e.order, 0);
        EXPECT_LT(e.order, minimumOrder);
        EXPECT_FALSE(e.extrapolated);
        EXPECT_EQ(e.value, values.back());
        EXPECT_NEAR(e.band, std::abs(values[2] - values[1]), 1e-15);
    }
    const RichardsonEstimate justAbove = richardson(sequence(cells, 0.2, 0.5, 0.6), cells);
    EXPECT_TRUE(justAbove.extrapolated);
    EXPECT_NEAR(justAbove.order, 0.6, 1e-9);
    EXPECT_NEAR(justAbove.value, 0.2, 1e-9);
}

// A section that converges at second order, sampled at each run's own points: the coarser runs are read at the
// finest run's points (linear between their own), the mean differences shrink by 4, the section's order is measured
// as 2 and every point's estimate is the limit.
TEST(Convergence, SectionsAreComparedAtTheFinestRunsPoints)
{
    std::vector<ConvergenceRun> runs;
    for (int n : {9, 17, 33})
    {
        ConvergenceRun run;
        run.size = std::to_string(n) + "x2x" + std::to_string(n);
        run.cellSize = 0.32 / Real(n - 1);
        run.thinnest = 0.2 + 3 * run.cellSize * run.cellSize;
        for (int i = 0; i < n; ++i)
        {
            const Real x = -0.16 + run.cellSize * Real(i);
            run.coordinate.push_back(x);
            // A straight profile (read exactly between points) offset by C h^2.
            run.ratio.push_back(0.5 + x + 3 * run.cellSize * run.cellSize);
        }
        runs.push_back(run);
    }
    const Convergence c = compareRuns(runs);
    ASSERT_EQ(c.coordinate.size(), 33u);
    EXPECT_NEAR(c.meanDifference[0] / c.meanDifference[1], 4, 1e-9);
    EXPECT_NEAR(c.sectionOrder.order, 2, 1e-6);
    for (std::size_t i = 0; i < c.coordinate.size(); ++i)
    {
        EXPECT_NEAR(c.estimate[i], 0.5 + c.coordinate[i], 1e-9) << "point " << i;
    }
    EXPECT_NEAR(c.thinnest.value, 0.2, 1e-9);
    const std::string csv = convergenceCsv(runs, c);
    EXPECT_EQ(csv.substr(0, csv.find('\n')), "coordinate_m,ratio_9x2x9,ratio_17x2x17,ratio_33x2x33,estimate,band");
}

// "N" keeps the scene's layers and aspect; "NxLxM" is taken as it is; fewer than two sizes, sizes out of order and
// malformed ones are refused naming --sizes.
TEST(Convergence, SizesAreReadAsTheFlagSays)
{
    LatticeSpec tray;
    tray.countX = 32;
    tray.layers = 2;
    tray.countZ = 25;
    EXPECT_EQ(convergenceSizes({"32", "64", "128"}, tray),
              (std::vector<std::string>{"32x2x25", "64x2x50", "128x2x100"}));
    EXPECT_EQ(convergenceSizes({"16x2x16", "33x2x25"}, tray), (std::vector<std::string>{"16x2x16", "33x2x25"}));
    for (const std::vector<std::string>& bad :
         {std::vector<std::string>{"32"}, std::vector<std::string>{"64", "32"}, std::vector<std::string>{"32", "32"},
          std::vector<std::string>{"32", "sixty"}, std::vector<std::string>{"32", "1"}})
    {
        try
        {
            convergenceSizes(bad, tray);
            ADD_FAILURE() << "accepted " << bad.size() << " sizes, the last " << bad.back();
        }
        catch (const InputError& error)
        {
            EXPECT_EQ(std::string(error.what()).rfind("--sizes: ", 0), 0u) << error.what();
        }
    }
}

// The band map reads a coarser run's bottom layer at a finer run's rest points: a field linear in x and z is read back
// exactly between the masses, also where the rows are shifted against each other along x (a triangular lattice's
// are), and a point beyond the sheet's edge takes the edge's value.
TEST(Convergence, ARestLayerFieldIsReadLinearlyBetweenItsMasses)
{
    RestLayerField field;
    field.rows = 3;
    field.columns = 4;
    const auto linear = [](Real x, Real z) { return 0.5 + 2 * x - 3 * z; };
    for (int row = 0; row < field.rows; ++row)
    {
        const Real z = 0.1 * row;
        field.z.push_back(z);
        for (int column = 0; column < field.columns; ++column)
        {
            const Real x = 0.1 * column + (row % 2 == 1 ? 0.05 : 0.0);
            field.x.push_back(x);
            field.ratio.push_back(linear(x, z));
        }
    }
    for (const auto& [x, z] : {std::pair<Real, Real>{0.12, 0.03}, {0.21, 0.17}, {0.05, 0.1}, {0.26, 0.0}})
    {
        EXPECT_NEAR(field.at(x, z), linear(x, z), 1e-12) << x << ", " << z;
    }
    EXPECT_NEAR(field.at(-1, 0), linear(0, 0), 1e-12);
    EXPECT_NEAR(field.at(1, 0.2), linear(0.3, 0.2), 1e-12);
    EXPECT_NEAR(field.at(0.1, 5), linear(0.1, 0.2), 1e-12);
}
