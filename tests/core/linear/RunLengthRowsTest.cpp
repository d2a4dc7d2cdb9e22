#include "core/linear/RunLengthRows.h"

#include "core/forces/SimdPath.h"

#include <gtest/gtest.h>

#include <Eigen/SparseCore>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>

namespace masse
{
namespace
{
/// The value of the finite half `bits`, from IEEE binary16's definition (independent of floatFromHalf).
double halfValue(std::uint16_t bits)
{
    const int exponent = (bits >> 10) & 0x1F;
    const int mantissa = bits & 0x3FF;
    const double magnitude =
        exponent == 0 ? std::ldexp(double(mantissa), -24) : std::ldexp(double(1024 + mantissa), exponent - 25);
    return (bits & 0x8000) ? -magnitude : magnitude;
}

bool finiteHalf(std::uint16_t bits)
{
    return ((bits >> 10) & 0x1F) != 0x1F;
}

/// IEEE's rounding to the nearest half, ties to even, by search (the reference; 0x7C00 past the largest finite half,
/// where IEEE rounds to infinity). The differences below are exact: the neighbours are within a factor of two of the
/// value, or zero.
std::uint16_t referenceHalf(double value)
{
    const double magnitude = std::abs(value);
    const auto sign = std::uint16_t(std::signbit(value) ? 0x8000 : 0);
    if (magnitude >= 65520.0)
    {
        return std::uint16_t(sign | 0x7C00);
    }
    std::uint16_t below = 0; // the largest half <= magnitude
    std::uint16_t step = 0x4000;
    while (step > 0)
    {
        const auto candidate = std::uint16_t(below + step);
        if (candidate <= 0x7BFF && halfValue(candidate) <= magnitude)
        {
            below = candidate;
        }
        step = std::uint16_t(step / 2);
    }
    if (below == 0x7BFF)
    {
        return std::uint16_t(sign | below); // between 65504 and 65520: down
    }
    const auto above = std::uint16_t(below + 1);
    const double down = magnitude - halfValue(below);
    const double up = halfValue(above) - magnitude;
    const bool toAbove = up < down || (up == down && (above & 1) == 0);
    return std::uint16_t(sign | (toAbove ? above : below));
}
#if defined(__x86_64__) && defined(__GNUC__)
/// rowDotAvx512 compiled for AVX-512 (it is inlined into its callers, which must be).
__attribute__((target("avx512f"))) float rowDotOnAvx512(const RunLengthRows::View& m, Eigen::Index row, const float* x)
{
    return rowDotAvx512(m, row, x);
}
#endif
} // namespace

// The factor's values are rounded to half precision in software (halfFromReal), so that the bits do not depend on the
// processor. Its rounding must be IEEE's to nearest, ties to even, straight from double: it is compared with a rounding
// by search over the halves' values (referenceHalf; clang 14 has no _Float16 on x86) on every finite half, on the
// midpoint between each pair of neighbours (a tie, where the even one wins) and just either side of it (where the
// nearest wins), and on a million random doubles spread over the halves' range, subnormals included. Past the largest
// finite half, where IEEE gives infinity, it clamps to 65504 instead. floatFromHalf reads every finite half back
// exactly.
TEST(RunLengthRows, HalfRoundingIsIeeeNearestEvenAndClampsInsteadOfOverflowing)
{
    for (std::uint32_t bits = 0; bits < 0x10000; ++bits)
    {
        const auto half = std::uint16_t(bits);
        if (!finiteHalf(half))
        {
            continue;
        }
        const double value = halfValue(half);
        ASSERT_EQ(double(floatFromHalf(half)), value) << "bits " << bits;
        ASSERT_EQ(halfFromReal(value), half) << "bits " << bits;
        const auto next = std::uint16_t(bits + 1);
        if ((bits & 0x7FFF) == 0x7BFF || !finiteHalf(next) || (bits & 0x8000) != (next & 0x8000))
        {
            continue;
        }
        const double midpoint = (value + halfValue(next)) / 2; // exact: a half has 11 bits
        for (const double probe : {midpoint, std::nextafter(midpoint, 0.0), std::nextafter(midpoint, 2 * midpoint)})
        {
            ASSERT_EQ(halfFromReal(probe), referenceHalf(probe)) << "between bits " << bits << " and the next";
        }
    }
    std::mt19937_64 random(7);
    std::uniform_real_distribution<double> exponent(-30.0, 16.0);
    std::uniform_int_distribution<int> sign(0, 1);
    for (int k = 0; k < 1000000; ++k)
    {
        const double value = (sign(random) ? -1.0 : 1.0) * std::exp2(exponent(random));
        if (std::abs(value) >= 65520.0)
        {
            ASSERT_EQ(halfFromReal(value) & 0x7FFF, 0x7BFF) << value;
            continue;
        }
        ASSERT_EQ(halfFromReal(value), referenceHalf(value)) << value;
    }
    EXPECT_EQ(halfFromReal(0.0), 0x0000);
    EXPECT_EQ(halfFromReal(-0.0), 0x8000);
    EXPECT_EQ(halfFromReal(65519.99), 0x7BFF); // IEEE rounds this down to 65504 as well
    EXPECT_EQ(referenceHalf(65520.0), 0x7C00); // ... and this up to infinity, which a factor must not hold
    EXPECT_EQ(halfFromReal(65520.0), 0x7BFF);
    EXPECT_EQ(halfFromReal(-1e300), 0xFBFF);
    EXPECT_EQ(halfFromReal(1e-300), 0x0000);
}

// A row's entries at most joinGap columns apart are stored as one run, the columns between as zeros; farther apart,
// as two. Row 60 of a lower triangular matrix has entries at columns 0-2, then joinGap after the last (joined), then
// joinGap + 1 after that (a new run), then a lone entry two columns on (joined): two runs. By columns (the backward
// solve's copy) the same entries, one to a row. Each row's dot product (by the default path's arithmetic, and the
// AVX-512 one's where the processor has it) is the exact sum of its own entries: the values and x are small integers
// and halves, so every sum is exact, and a stored zero adds nothing.
TEST(RunLengthRows, RowsEntriesCloseTogetherShareARunThroughStoredZeros)
{
    const Eigen::Index n = 200;
    const Eigen::Index row = n - 1;
    const auto gap = Eigen::Index(RunLengthRows::joinGap);
    std::vector<Eigen::Index> columns = {0, 1, 2};
    columns.push_back(columns.back() + gap);     // joined: joinGap - 1 zeros between
    columns.push_back(columns.back() + gap + 1); // a new run
    columns.push_back(columns.back() + 2);       // joined: one zero between
    ASSERT_LT(columns.back(), row);
    std::vector<Eigen::Triplet<Real>> triplets;
    for (std::size_t k = 0; k < columns.size(); ++k)
    {
        triplets.emplace_back(row, columns[k], Real(k + 1) * 0.5);
    }
    Eigen::SparseMatrix<Real> lower(n, n);
    lower.setFromTriplets(triplets.begin(), triplets.end());
    std::vector<float> x(static_cast<std::size_t>(n));
    for (std::size_t i = 0; i < x.size(); ++i)
    {
        x[i] = float(int(i % 7) - 3);
    }
    float exact = 0;
    for (std::size_t k = 0; k < columns.size(); ++k)
    {
        exact += float(Real(k + 1) * 0.5) * x[std::size_t(columns[k])];
    }
    ASSERT_NE(exact, 0.0f);

    RunLengthRows byRows;
    byRows.assignLowerRows(lower);
    EXPECT_EQ(byRows.runs(), 2u);
    EXPECT_EQ(byRows.entries(), std::size_t(columns[3] + 1 + 3)); // columns 0 to the fourth entry's, then three
    const RunLengthRows::View rows = byRows.view();
    EXPECT_EQ(rowDot(rows, row, x.data(), floatFromHalf), exact);
    for (Eigen::Index other = 0; other < row; ++other)
    {
        EXPECT_EQ(rowDot(rows, other, x.data(), floatFromHalf), 0.0f);
    }
#if defined(__x86_64__) && defined(__GNUC__)
    if (simdPathSupported(SimdPath::Avx512))
    {
        EXPECT_EQ(rowDotOnAvx512(rows, row, x.data()), exact);
    }
#endif

    RunLengthRows byColumns;
    byColumns.assignLowerColumnsLastFirst(lower);
    EXPECT_EQ(byColumns.runs(), columns.size()); // each column holds one entry, in row 199
    EXPECT_EQ(byColumns.entries(), columns.size());
}

namespace
{
/// The stored halves of every row of `m`, run by run.
std::vector<std::uint16_t> storedValues(const RunLengthRows& m)
{
    const RunLengthRows::View view = m.view();
    return std::vector<std::uint16_t>(view.values, view.values + m.entries());
}
} // namespace

// A refresh writes the factor's new values into the runs laid out for its pattern (refill) instead of laying them out
// again (assign). On a random lower triangular pattern with runs both joined through zeros and apart, refilling the
// copies of one matrix with another's values (the same pattern, other values, some of them zero) gives, bit for bit,
// the copies assigned from the other: the same runs and the same halves, the joined runs' zeros still zero.
TEST(RunLengthRows, RefillingTheValuesOfTheSamePatternGivesWhatAssigningThemGives)
{
    const Eigen::Index n = 300;
    std::mt19937_64 random(11);
    std::uniform_int_distribution<int> skip(1, 2 * RunLengthRows::joinGap);
    std::uniform_real_distribution<double> value(-2.0, 2.0);
    std::vector<Eigen::Triplet<Real>> first;
    std::vector<Eigen::Triplet<Real>> second;
    for (Eigen::Index column = 0; column < n; ++column)
    {
        for (Eigen::Index row = column + skip(random); row < n; row += skip(random))
        {
            first.emplace_back(row, column, value(random));
            second.emplace_back(row, column, (row + column) % 5 == 0 ? 0.0 : value(random));
        }
    }
    Eigen::SparseMatrix<Real> a(n, n);
    Eigen::SparseMatrix<Real> b(n, n);
    a.setFromTriplets(first.begin(), first.end());
    b.setFromTriplets(second.begin(), second.end());
    ASSERT_EQ(a.nonZeros(), b.nonZeros());

    RunLengthRows refilledRows;
    RunLengthRows refilledColumns;
    refilledRows.assignLowerRows(a);
    refilledColumns.assignLowerColumnsLastFirst(a);
    refilledRows.refillLowerRows(b);
    refilledColumns.refillLowerColumnsLastFirst(b);
    RunLengthRows assignedRows;
    RunLengthRows assignedColumns;
    assignedRows.assignLowerRows(b);
    assignedColumns.assignLowerColumnsLastFirst(b);

    ASSERT_GT(assignedRows.entries(), std::size_t(a.nonZeros())); // some runs joined through zeros
    ASSERT_GT(assignedRows.runs(), std::size_t(n));               // and some rows in several runs
    EXPECT_EQ(refilledRows.runs(), assignedRows.runs());
    EXPECT_EQ(refilledColumns.runs(), assignedColumns.runs());
    EXPECT_EQ(storedValues(refilledRows), storedValues(assignedRows));
    EXPECT_EQ(storedValues(refilledColumns), storedValues(assignedColumns));
    EXPECT_NE(storedValues(refilledRows),
              [&]
              {
                  RunLengthRows fromA;
                  fromA.assignLowerRows(a);
                  return storedValues(fromA);
              }());
}
} // namespace masse
