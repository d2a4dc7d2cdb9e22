#include "core/linear/MassBlockRows.h"

#include "core/forces/SimdPath.h"
#include "support/TestSystems.h"

#include <gtest/gtest.h>

#include <Eigen/SparseCore>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <iterator>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

namespace masse
{
namespace
{
#if defined(__x86_64__) && defined(__GNUC__)
/// The AVX-512 kernels compiled for AVX-512 (they are inlined into their callers, which must be).
__attribute__((target("avx512f"))) void blockDotsOnAvx512(const MassBlockRows::View& m, Eigen::Index block,
                                                          const float* x, float s[3])
{
    blockDotsAvx512(m, block, x, s);
}
__attribute__((target("avx512f"))) void blockScatterOnAvx512(const MassBlockRows::View& m, Eigen::Index block,
                                                             const float x[3], float* w)
{
    blockScatterAvx512(m, block, x, w);
}
/// The AVX2 kernels compiled for AVX2 and F16C.
__attribute__((target("avx2,f16c"))) void blockDotsOnAvx2(const MassBlockRows::View& m, Eigen::Index block,
                                                          const float* x, float s[3])
{
    blockDotsAvx2(m, block, x, s);
}
__attribute__((target("avx2,f16c"))) void blockScatterOnAvx2(const MassBlockRows::View& m, Eigen::Index block,
                                                             const float x[3], float* w)
{
    blockScatterAvx2(m, block, x, w);
}
#endif

bool avx2()
{
    return simdPathSupported(SimdPath::Avx2);
}

bool avx512()
{
    return simdPathSupported(SimdPath::Avx512);
}

/// The stored halves of every block, run by run.
std::vector<std::uint16_t> storedValues(const MassBlockRows& m)
{
    const MassBlockRows::View view = m.laidOut();
    return std::vector<std::uint16_t>(view.values, view.values + m.entries());
}

/// The bits of `values`, so that +0 and -0 differ (and a NaN equals itself).
std::vector<std::uint32_t> bitsOf(const std::vector<float>& values)
{
    std::vector<std::uint32_t> bits(values.size());
    std::memcpy(bits.data(), values.data(), values.size() * sizeof(float));
    return bits;
}

std::vector<float> inBlockValues(const MassBlockRows& m)
{
    const MassBlockRows::View view = m.view();
    return std::vector<float>(view.inBlock, view.inBlock + 3 * m.blocks());
}

/// `size` values drawn evenly from [-1, 1) with `seed`.
std::vector<float> randomVector(std::size_t size, std::uint64_t seed)
{
    std::mt19937_64 random(seed);
    std::uniform_real_distribution<float> value(-1.0f, 1.0f);
    std::vector<float> x(size);
    for (float& xi : x)
    {
        xi = value(random);
    }
    return x;
}

/// A random lower triangular matrix of `masses` masses (three rows each): each row's own pattern below its mass (rows
/// of one mass share some columns and not others, so a block's runs are their union), and its mass's block full. The
/// pattern depends on the seed alone; `someZeros` makes a fifth of the values below the blocks zero.
MassBlockRows::SparseMatrix randomLower(Eigen::Index masses, std::uint64_t seed, bool someZeros)
{
    const Eigen::Index n = 3 * masses;
    std::mt19937_64 random(seed);
    std::uniform_int_distribution<int> skip(1, 2 * MassBlockRows::joinGap);
    std::uniform_real_distribution<double> value(-2.0, 2.0);
    std::vector<Eigen::Triplet<float>> triplets;
    for (Eigen::Index row = 0; row < n; ++row)
    {
        const Eigen::Index first = row - row % 3;
        for (Eigen::Index column = skip(random) - 1; column < first; column += skip(random))
        {
            const double drawn = value(random); // drawn whether kept or not, so that both patterns are the same
            triplets.emplace_back(row, column, someZeros && (row + column) % 5 == 0 ? 0.0 : drawn);
        }
        for (Eigen::Index column = first; column < row; ++column)
        {
            triplets.emplace_back(row, column, value(random));
        }
    }
    MassBlockRows::SparseMatrix lower(n, n);
    lower.setFromTriplets(triplets.begin(), triplets.end());
    return lower;
}
} // namespace

// A block's shared columns at most joinGap apart are stored as one run, the columns between as zeros; farther apart,
// as two. Mass 60's rows 180 and 182 have entries at columns 0-2, then joinGap after the last (joined), then
// joinGap + 1 after that (a new run), then a lone entry two columns on (joined); row 181 has all but the last, so its
// value there is a stored zero: two runs. Each row's sum (blockDots) and each column's scattered sum (blockScatter),
// by the default path's arithmetic and the AVX2 and AVX-512 ones' where the processor has them, are the exact sums of
// the row's and the column's own entries: the values and x are small integers and halves, so every sum is exact, and a
// stored zero adds nothing. The block's own entries are kept apart, and no other block has a run.
TEST(MassBlockRows, ABlocksRowsShareRunsThroughStoredZeros)
{
    const Eigen::Index masses = 70;
    const Eigen::Index n = 3 * masses;
    const Eigen::Index block = 60;
    const auto gap = Eigen::Index(MassBlockRows::joinGap);
    std::vector<Eigen::Index> columns = {0, 1, 2};
    columns.push_back(columns.back() + gap);     // joined: joinGap - 1 zeros between
    columns.push_back(columns.back() + gap + 1); // a new run
    columns.push_back(columns.back() + 2);       // joined: one zero between
    ASSERT_LT(columns.back(), 3 * block);
    const auto value = [](Eigen::Index row, std::size_t k) { return Real(int(k) + 1 + int(row % 3)) * 0.5; };
    std::vector<Eigen::Triplet<float>> triplets;
    for (Eigen::Index row = 3 * block; row < 3 * block + 3; ++row)
    {
        const std::size_t count = row % 3 == 1 ? columns.size() - 1 : columns.size();
        for (std::size_t k = 0; k < count; ++k)
        {
            triplets.emplace_back(row, columns[k], value(row, k));
        }
    }
    triplets.emplace_back(3 * block + 1, 3 * block, 0.25);
    triplets.emplace_back(3 * block + 2, 3 * block, -0.5);
    triplets.emplace_back(3 * block + 2, 3 * block + 1, 0.75);
    MassBlockRows::SparseMatrix lower(n, n);
    lower.setFromTriplets(triplets.begin(), triplets.end());

    MassBlockRows rows;
    rows.assignLowerRows(lower);
    EXPECT_EQ(rows.blocks(), masses);
    EXPECT_EQ(rows.runs(), 2u);
    EXPECT_EQ(rows.entries(), 3 * std::size_t(columns[3] + 1 + 3)); // columns 0 to the fourth entry's, then three
    EXPECT_EQ(inBlockValues(rows)[3 * block], 0.25f);
    EXPECT_EQ(inBlockValues(rows)[3 * block + 1], -0.5f);
    EXPECT_EQ(inBlockValues(rows)[3 * block + 2], 0.75f);

    std::vector<float> x(static_cast<std::size_t>(n));
    for (std::size_t i = 0; i < x.size(); ++i)
    {
        x[i] = float(int(i % 7) - 3);
    }
    float exact[3] = {};
    for (int line = 0; line < 3; ++line)
    {
        const std::size_t count = line == 1 ? columns.size() - 1 : columns.size();
        for (std::size_t k = 0; k < count; ++k)
        {
            exact[line] += float(value(3 * block + line, k)) * x[std::size_t(columns[k])];
        }
        ASSERT_NE(exact[line], 0.0f);
    }
    const MassBlockRows::View view = rows.view();
    float s[3];
    blockDots(view, block, x.data(), floatFromHalf, s);
    EXPECT_EQ(std::vector<float>(s, s + 3), std::vector<float>(exact, exact + 3));
    for (Eigen::Index other = 0; other < masses; ++other)
    {
        if (other != block)
        {
            blockDots(view, other, x.data(), floatFromHalf, s);
            EXPECT_EQ(std::vector<float>(s, s + 3), std::vector<float>(3, 0.0f)) << "block " << other;
        }
    }

    const float solved[3] = {1.0f, 2.0f, -1.0f};
    std::vector<float> expected(static_cast<std::size_t>(n), 0.0f);
    for (int line = 0; line < 3; ++line)
    {
        const std::size_t count = line == 1 ? columns.size() - 1 : columns.size();
        for (std::size_t k = 0; k < count; ++k)
        {
            expected[std::size_t(columns[k])] += float(value(3 * block + line, k)) * solved[line];
        }
    }
    std::vector<float> w(static_cast<std::size_t>(n), 0.0f);
    blockScatter(view, block, solved, w.data(), floatFromHalf);
    EXPECT_EQ(w, expected);
#if defined(__x86_64__) && defined(__GNUC__)
    if (avx2())
    {
        blockDotsOnAvx2(view, block, x.data(), s);
        EXPECT_EQ(std::vector<float>(s, s + 3), std::vector<float>(exact, exact + 3));
        std::vector<float> wAvx2(static_cast<std::size_t>(n), 0.0f);
        blockScatterOnAvx2(view, block, solved, wAvx2.data());
        EXPECT_EQ(wAvx2, expected);
    }
    if (avx512())
    {
        blockDotsOnAvx512(view, block, x.data(), s);
        EXPECT_EQ(std::vector<float>(s, s + 3), std::vector<float>(exact, exact + 3));
        std::vector<float> wAvx512(static_cast<std::size_t>(n), 0.0f);
        blockScatterOnAvx512(view, block, solved, wAvx512.data());
        EXPECT_EQ(wAvx512, expected);
    }
#endif
}

// A refresh writes the factor's new values into the runs laid out for its pattern (refill) instead of laying them out
// again (assign). On a random pattern whose rows of one mass differ (a block's runs are their union), with runs both
// joined through zeros and apart, refilling the copy of one matrix with another's values (the same pattern, other
// values, some of them zero) gives, bit for bit, the copy assigned from the other: the same runs and the same halves,
// the joined runs' zeros still zero.
TEST(MassBlockRows, RefillingTheValuesOfTheSamePatternGivesWhatAssigningThemGives)
{
    const MassBlockRows::SparseMatrix a = randomLower(100, 11, false);
    const MassBlockRows::SparseMatrix b = randomLower(100, 11, true);
    ASSERT_EQ(a.nonZeros(), b.nonZeros());

    MassBlockRows refilled;
    refilled.assignLowerRows(a);
    const std::vector<std::uint16_t> fromA = storedValues(refilled);
    refilled.refillLowerRows(b);
    MassBlockRows assigned;
    assigned.assignLowerRows(b);

    ASSERT_GT(assigned.entries(), std::size_t(a.nonZeros())); // the rows' unions, and runs joined through zeros
    ASSERT_GT(assigned.runs(), std::size_t(100));             // some blocks in several runs
    EXPECT_EQ(refilled.runs(), assigned.runs());
    EXPECT_EQ(storedValues(refilled), storedValues(assigned));
    EXPECT_EQ(inBlockValues(refilled), inBlockValues(assigned));
    EXPECT_NE(storedValues(refilled), fromA);

    // A factor of another pattern is refused: its values would land in the places of the pattern laid out.
    EXPECT_THROW(refilled.refillLowerRows(randomLower(99, 11, false)), std::invalid_argument);
}

// A refill rounds the factor's single-precision values to half with F16C's conversion on the AVX2 and AVX-512 paths
// and with halfFromReal on the default one: the same halves and in-block values on every path, on a factor whose
// values span all the halves' kinds (subnormal, normal, ties between two halves, past the largest half, both zeros,
// infinities and a NaN).
TEST(MassBlockRows, ARefillHasTheSameHalvesOnEveryPath)
{
    MassBlockRows::SparseMatrix lower = randomLower(200, 13, false);
    std::mt19937_64 random(5);
    std::uniform_real_distribution<float> exponent(-30.0f, 17.0f);
    const float special[] = {0.0f,
                             -0.0f,
                             65504.0f,
                             65519.0f,
                             65520.0f,
                             -1e30f,
                             1e-30f,
                             5.9604645e-8f,
                             2.9802322e-8f,
                             1.0f + 1.0f / 2048.0f, // a tie between 1 and its next half: to 1, the even one
                             1.0f + 3.0f / 2048.0f, // a tie: up to the even one
                             std::numeric_limits<float>::infinity(),
                             -std::numeric_limits<float>::infinity(),
                             std::numeric_limits<float>::quiet_NaN()};
    for (Eigen::Index k = 0; k < lower.nonZeros(); ++k)
    {
        const auto index = std::size_t(k);
        lower.valuePtr()[k] =
            index < std::size(special) ? special[index] : (index % 2 ? -1.0f : 1.0f) * std::exp2(exponent(random));
    }
    const test::SimdPathGuard guard;
    setSimdPath(SimdPath::Default);
    MassBlockRows reference;
    reference.assignLowerRows(lower);
    for (const SimdPath path : supportedSimdPaths())
    {
        setSimdPath(path);
        MassBlockRows rows;
        rows.assignLowerRows(lower);
        EXPECT_EQ(storedValues(rows), storedValues(reference)) << simdPathName(path);
        EXPECT_EQ(bitsOf(inBlockValues(rows)), bitsOf(inBlockValues(reference))) << simdPathName(path);
    }
}

// The masses a sheet's contact holds have zero rows and columns in the factor, and so has the fill through them. The
// solves read the runs with their all-zero groups of sixteen columns left out (view()), and get the bits of reading
// every run as laid out (laidOut()): each block's three sums and the sums every block scatters into the columns below
// it, by the default path and by the AVX-512 one, on a random factor whose masses 40 to 89 are held (their rows and
// columns zero) and a vector of both signs (so the left-out products would have been -0 and +0). The groups left out
// are the all-zero ones and no others: the values read are the laid-out values of the groups that are not all zero.
TEST(MassBlockRows, TheSolvesLeaveOutAllZeroGroupsWithTheSameBits)
{
    const Eigen::Index masses = 150;
    MassBlockRows::SparseMatrix lower = randomLower(masses, 7, false);
    const auto held = [](Eigen::Index row) { return row / 3 >= 40 && row / 3 < 90; };
    for (Eigen::Index column = 0; column < lower.outerSize(); ++column)
    {
        for (MassBlockRows::SparseMatrix::InnerIterator it(lower, column); it; ++it)
        {
            if (held(it.row()) || held(column))
            {
                it.valueRef() = 0;
            }
        }
    }
    MassBlockRows rows;
    rows.assignLowerRows(lower);
    const MassBlockRows::View live = rows.view();
    const MassBlockRows::View laidOut = rows.laidOut();

    std::size_t nonZeroGroupValues = 0;
    for (std::size_t r = 0; r < rows.runs(); ++r)
    {
        const int length = laidOut.runLength[r];
        for (int t = 0; t < length; t += 16)
        {
            const int count = 3 * std::min(16, length - t);
            const std::uint16_t* group = laidOut.values + laidOut.runStart[r] + 3 * t;
            nonZeroGroupValues += std::any_of(group, group + count, [](std::uint16_t v) { return (v & 0x7FFF) != 0; })
                                      ? std::size_t(count)
                                      : 0;
        }
    }
    EXPECT_EQ(rows.liveEntries(), nonZeroGroupValues);
    EXPECT_LT(rows.liveEntries(), rows.entries() * 3 / 4); // a third of the masses held leave out much of the factor
    EXPECT_GT(rows.liveEntries(), rows.entries() / 4);

    const std::vector<float> x = randomVector(std::size_t(3 * masses), 9);
    std::vector<float> wLaidOut(x.size(), 0.0f);
    std::vector<float> wLive(x.size(), 0.0f);
    std::vector<float> wLiveAvx2(x.size(), 0.0f);
    std::vector<float> wLiveAvx512(x.size(), 0.0f);
    for (Eigen::Index block = masses - 1; block >= 0; --block)
    {
        std::vector<float> sLaidOut(3);
        std::vector<float> sLive(3);
        blockDots(laidOut, block, x.data(), floatFromHalf, sLaidOut.data());
        blockDots(live, block, x.data(), floatFromHalf, sLive.data());
        ASSERT_EQ(bitsOf(sLive), bitsOf(sLaidOut)) << "block " << block;
        blockScatter(laidOut, block, x.data() + 3 * block, wLaidOut.data(), floatFromHalf);
        blockScatter(live, block, x.data() + 3 * block, wLive.data(), floatFromHalf);
#if defined(__x86_64__) && defined(__GNUC__)
        if (avx2())
        {
            blockDotsOnAvx2(live, block, x.data(), sLive.data());
            ASSERT_EQ(bitsOf(sLive), bitsOf(sLaidOut)) << "block " << block << ", AVX2";
            blockScatterOnAvx2(live, block, x.data() + 3 * block, wLiveAvx2.data());
        }
        if (avx512())
        {
            blockDotsOnAvx512(live, block, x.data(), sLive.data());
            ASSERT_EQ(bitsOf(sLive), bitsOf(sLaidOut)) << "block " << block << ", AVX-512";
            blockScatterOnAvx512(live, block, x.data() + 3 * block, wLiveAvx512.data());
        }
#endif
    }
    EXPECT_EQ(bitsOf(wLive), bitsOf(wLaidOut));
    if (avx2())
    {
        EXPECT_EQ(bitsOf(wLiveAvx2), bitsOf(wLaidOut));
    }
    if (avx512())
    {
        EXPECT_EQ(bitsOf(wLiveAvx512), bitsOf(wLaidOut));
    }
}

// The AVX2 and AVX-512 kernels give the default path's bits on a random matrix and vector, runs of every length: each
// block's three sums, and the sums every block scatters into the columns below it, in the backward solve's order.
TEST(MassBlockRows, TheVectorKernelsGiveTheDefaultPathsBits)
{
    if (!avx2())
    {
        // Skipped without AVX2: there is no second path to compare (the default path is checked exactly above).
        GTEST_SKIP() << "this processor has no AVX2";
    }
#if defined(__x86_64__) && defined(__GNUC__)
    const Eigen::Index masses = 150;
    const MassBlockRows::SparseMatrix lower = randomLower(masses, 5, true);
    MassBlockRows rows;
    rows.assignLowerRows(lower);
    const MassBlockRows::View view = rows.view();
    const std::vector<float> x = randomVector(std::size_t(3 * masses), 3);
    std::vector<float> wDefault(x.size(), 0.0f);
    std::vector<float> wAvx2(x.size(), 0.0f);
    std::vector<float> wAvx512(x.size(), 0.0f);
    for (Eigen::Index block = masses - 1; block >= 0; --block)
    {
        std::vector<float> sDefault(3);
        std::vector<float> sVector(3);
        blockDots(view, block, x.data(), floatFromHalf, sDefault.data());
        blockDotsOnAvx2(view, block, x.data(), sVector.data());
        ASSERT_EQ(bitsOf(sVector), bitsOf(sDefault)) << "block " << block << ", AVX2";
        if (avx512())
        {
            blockDotsOnAvx512(view, block, x.data(), sVector.data());
            ASSERT_EQ(bitsOf(sVector), bitsOf(sDefault)) << "block " << block << ", AVX-512";
            blockScatterOnAvx512(view, block, x.data() + 3 * block, wAvx512.data());
        }
        blockScatter(view, block, x.data() + 3 * block, wDefault.data(), floatFromHalf);
        blockScatterOnAvx2(view, block, x.data() + 3 * block, wAvx2.data());
    }
    EXPECT_EQ(bitsOf(wAvx2), bitsOf(wDefault));
    if (avx512())
    {
        EXPECT_EQ(bitsOf(wAvx512), bitsOf(wDefault));
    }
#endif
}

// A factor that is not three rows a mass is refused by name rather than stored short of its last rows.
TEST(MassBlockRows, AFactorThatIsNotThreeRowsAMassIsRefused)
{
    MassBlockRows rows;
    EXPECT_THROW(rows.assignLowerRows(MassBlockRows::SparseMatrix(10, 10)), std::invalid_argument);
    EXPECT_THROW(rows.assignLowerRows(MassBlockRows::SparseMatrix(9, 6)), std::invalid_argument);
    EXPECT_NO_THROW(rows.assignLowerRows(MassBlockRows::SparseMatrix(9, 9)));
    EXPECT_EQ(rows.blocks(), 3);
}
} // namespace masse
