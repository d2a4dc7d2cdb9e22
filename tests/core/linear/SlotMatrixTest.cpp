// The sparse block/slot matrix the implicit step and the heat model assemble into: blocks reached through slots land
// where a dense assembly puts them, bit for bit, and a block the pattern does not hold is refused.

#include "core/linear/SlotMatrix.h"
#include "core/InputError.h"
#include "core/linear/ConjugateGradient.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <vector>

using namespace masse;

namespace
{
/// A chain 0-1-2-3 with a brace 0-2 and the spring 1-2 listed twice (two springs may join the same masses).
const std::vector<SpringEnds> chainEnds = {{0, 1}, {1, 2}, {2, 3}, {0, 2}, {2, 1}};
constexpr std::size_t chainMasses = 4;

/// A block with distinct entries and no symmetry, so a transposed or misplaced write shows.
template <int B> Eigen::Matrix<Real, B, B> distinctBlock(int seed)
{
    Eigen::Matrix<Real, B, B> block;
    for (int c = 0; c < B; ++c)
    {
        for (int r = 0; r < B; ++r)
        {
            block(r, c) = Real(seed) + Real(0.1) * Real(r) + Real(0.01) * Real(c) + Real(1) / Real(3 + seed);
        }
    }
    return block;
}

/// Assembles a mass block per mass and, per spring s with block K, K on both ends' diagonals, -K at (a, b) and -K^T at
/// (b, a): through the slots, and into a dense matrix by index in the same order. The two must agree exactly.
template <int B> void expectSlotAssemblyEqualsDense()
{
    SlotMatrix<B> matrix;
    matrix.build(chainMasses, chainEnds);
    Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic> dense =
        Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic>::Zero(B * chainMasses, B * chainMasses);
    auto denseBlock = [&](std::size_t row, std::size_t column)
    { return dense.template block<B, B>(Eigen::Index(B * row), Eigen::Index(B * column)); };

    for (std::size_t i = 0; i < chainMasses; ++i)
    {
        const auto block = distinctBlock<B>(int(i));
        matrix.add(matrix.diagonal(i), block);
        denseBlock(i, i) += block;
    }
    for (std::size_t s = 0; s < chainEnds.size(); ++s)
    {
        const auto block = distinctBlock<B>(10 + int(s));
        const std::size_t a = std::size_t(chainEnds[s].a);
        const std::size_t b = std::size_t(chainEnds[s].b);
        matrix.add(matrix.diagonal(a), block);
        matrix.add(matrix.diagonal(b), block);
        matrix.add(matrix.ab(s), -block);
        matrix.add(matrix.ba(s), -block.transpose());
        denseBlock(a, a) += block;
        denseBlock(b, b) += block;
        denseBlock(a, b) -= block;
        denseBlock(b, a) -= block.transpose();
    }
    const Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic> assembled = matrix.matrix().toDense();
    EXPECT_EQ(assembled, dense); // exact: the same numbers summed in the same order

    // Masses 1 and 3 share no spring: their blocks are outside the pattern, not stored zeros.
    const std::size_t heldBlocks = chainMasses + 2 * 4; // four distinct pairs: 0-1, 1-2, 2-3, 0-2
    EXPECT_EQ(std::size_t(matrix.matrix().nonZeros()), std::size_t(B * B) * heldBlocks);
    EXPECT_EQ((dense.template block<B, B>(B * 1, B * 3)), (Eigen::Matrix<Real, B, B>::Zero()));

    // Both listings of the spring 1-2 reach the same places.
    EXPECT_EQ(matrix.ab(1), matrix.ba(4));
    EXPECT_EQ(matrix.ba(1), matrix.ab(4));
    EXPECT_EQ(matrix.ab(0), matrix.slotsOf(0, 1));

    // read returns what write stored; setZero clears the values and keeps the pattern.
    const auto written = distinctBlock<B>(99);
    matrix.write(matrix.ab(3), written);
    EXPECT_EQ(matrix.read(matrix.ab(3)), written);
    EXPECT_EQ(matrix.read(matrix.ba(3)), (dense.template block<B, B>(B * 2, 0)));
    matrix.setZero();
    EXPECT_EQ(std::size_t(matrix.matrix().nonZeros()), std::size_t(B * B) * heldBlocks);
    EXPECT_EQ(matrix.matrix().toDense().cwiseAbs().maxCoeff(), Real(0));
}
} // namespace

TEST(SlotMatrix, BlocksThroughSlotsEqualDenseAssembly3x3)
{
    expectSlotAssemblyEqualsDense<3>();
}

TEST(SlotMatrix, BlocksThroughSlotsEqualDenseAssemblyScalar)
{
    expectSlotAssemblyEqualsDense<1>();
    SlotMatrix<1> matrix;
    matrix.build(chainMasses, chainEnds);
    matrix.value(matrix.diagonal(2)) = 5;
    matrix.value(matrix.ab(2)) -= 2;
    EXPECT_EQ(matrix.matrix().coeff(2, 2), Real(5));
    EXPECT_EQ(matrix.matrix().coeff(2, 3), Real(-2));
    EXPECT_EQ(matrix.matrix().coeff(3, 2), Real(0));
}

TEST(SlotMatrix, BlockWithoutSpringIsRefused)
{
    SlotMatrix<3> matrix;
    matrix.build(chainMasses, chainEnds);
    EXPECT_THROW(matrix.slotsOf(1, 3), std::out_of_range); // no spring joins 1 and 3
    EXPECT_THROW(matrix.slotsOf(3, 0), std::out_of_range);
    EXPECT_THROW(matrix.slotsOf(0, chainMasses), std::out_of_range); // past the last mass
    EXPECT_NO_THROW(matrix.slotsOf(2, 0));
}

TEST(SlotMatrix, TooManyMassesIsAnInputError)
{
    SlotMatrix<3> matrix;
    // Refused before anything is allocated.
    EXPECT_THROW(matrix.build(SlotMatrix<3>::maxMasses() + 1, {}), InputError);
    EXPECT_GT(SlotMatrix<1>::maxMasses(), SlotMatrix<3>::maxMasses());
}

namespace
{
/// x for the product tests: distinct values of both signs, none of them exact in binary.
Vector productInput(Eigen::Index size)
{
    Vector x(size);
    for (Eigen::Index i = 0; i < x.size(); ++i)
    {
        x[i] = Real(1) / Real(3 + i) - Real(0.37) * Real(i % 5);
    }
    return x;
}
} // namespace

// The conjugate gradient's product (multiplySymmetricRows) sums a mass's three rows together where they share their
// columns: each row's sum must be the plain one-row loop's, bit for bit, over the whole matrix and over row ranges
// that cut a mass's rows apart; a matrix of scalar blocks, whose neighbouring rows mostly differ, too.
template <int B> void expectProductIsEachRowsPlainSum()
{
    SlotMatrix<B> matrix;
    matrix.build(chainMasses, chainEnds);
    for (std::size_t i = 0; i < chainMasses; ++i)
    {
        matrix.add(matrix.diagonal(i), distinctBlock<B>(int(i)));
    }
    for (std::size_t s = 0; s < chainEnds.size(); ++s)
    {
        const auto block = distinctBlock<B>(10 + int(s));
        matrix.add(matrix.ab(s), -block);
        matrix.add(matrix.ba(s), -block.transpose());
    }
    const SparseMatrix& a = matrix.matrix();
    Vector x = productInput(a.rows());
    Vector expected(a.rows());
    for (Eigen::Index row = 0; row < a.rows(); ++row)
    {
        Real sum = 0;
        for (SparseMatrix::InnerIterator it(a, row); it; ++it)
        {
            sum += it.value() * x[it.index()];
        }
        expected[row] = sum;
    }
    for (const Eigen::Index begin : {Eigen::Index(0), Eigen::Index(1), Eigen::Index(2)})
    {
        Vector y = Vector::Constant(a.rows(), -1);
        multiplySymmetricRows(a, x, y, begin, a.rows() - (begin == 1 ? 1 : 0));
        for (Eigen::Index row = begin; row < a.rows() - (begin == 1 ? 1 : 0); ++row)
        {
            EXPECT_EQ(y[row], expected[row]) << "row " << row << " from " << begin;
        }
    }
    EXPECT_EQ(rowsComeInThrees(a), B == 3) << "a mass's rows share their columns in the 3x3 matrix alone";
    if constexpr (B == 3)
    {
        // Without looking at the columns: the same sums, over the whole matrix and from a later mass.
        for (const Eigen::Index begin : {Eigen::Index(0), Eigen::Index(3)})
        {
            Vector y = Vector::Constant(a.rows(), -1);
            multiplyMassRows(a, x, y, begin, a.rows());
            for (Eigen::Index row = 0; row < a.rows(); ++row)
            {
                EXPECT_EQ(y[row], row < begin ? Real(-1) : expected[row]) << "row " << row << " from " << begin;
            }
        }
    }
}

TEST(SlotMatrix, ProductSumsEachRowInItsOwnOrder)
{
    expectProductIsEachRowsPlainSum<3>();
    expectProductIsEachRowsPlainSum<1>();
}

// A pinned or held mass's rows of the implicit matrix are the identity's: a one on the diagonal, and its blocks with
// every other mass zeros of either sign (the filter's zeros times the blocks). The product told which masses those are
// takes their rows as x's own and gets the bits of summing them, signed zeros included: masses 1 and 3 of the chain
// held, their blocks' zeros -0 and +0, and x -0 at one of their coordinates and of both signs elsewhere.
TEST(SlotMatrix, ProductTakesIdentityRowsAsTheyAreWithTheSameBits)
{
    SlotMatrix<3> matrix;
    matrix.build(chainMasses, chainEnds);
    const auto held = [](Index mass) { return mass == 1 || mass == 3; };
    for (std::size_t i = 0; i < chainMasses; ++i)
    {
        matrix.add(matrix.diagonal(i), held(Index(i)) ? Mat3(Mat3::Identity()) : distinctBlock<3>(int(i)));
    }
    for (std::size_t s = 0; s < chainEnds.size(); ++s)
    {
        const Mat3 block = distinctBlock<3>(10 + int(s));
        if (held(chainEnds[s].a) || held(chainEnds[s].b))
        {
            matrix.write(matrix.ab(s), Real(0) * block); // zeros with the block's signs
            matrix.write(matrix.ba(s), Real(0) * -block.transpose());
            continue;
        }
        matrix.add(matrix.ab(s), -block);
        matrix.add(matrix.ba(s), -block.transpose());
    }
    const SparseMatrix& a = matrix.matrix();
    Vector x = productInput(a.rows());
    x[4] = -Real(0); // mass 1's second coordinate
    std::vector<std::uint8_t> identity(chainMasses, 0);
    identity[1] = identity[3] = 1;
    Vector summed = Vector::Constant(a.rows(), -1);
    Vector taken = Vector::Constant(a.rows(), -1);
    multiplyMassRows(a, x, summed, 0, a.rows());
    multiplyMassRows(a, x, taken, 0, a.rows(), identity.data());
    ASSERT_EQ(std::memcmp(summed.data(), taken.data(), std::size_t(a.rows()) * sizeof(Real)), 0);
    EXPECT_FALSE(std::signbit(taken[4]));
    EXPECT_EQ(taken[3], x[3]);
}

namespace
{
/// The pattern setFromTriplets makes from every block the matrix holds (each mass's own, both of each spring's).
template <int B> SparseMatrix patternFromTriplets(std::size_t masses, const std::vector<SpringEnds>& ends)
{
    std::vector<Eigen::Triplet<Real, SparseMatrix::StorageIndex>> triplets;
    const auto addBlock = [&](std::size_t row, std::size_t column)
    {
        for (int c = 0; c < B; ++c)
        {
            for (int r = 0; r < B; ++r)
            {
                triplets.emplace_back(int(B * row) + r, int(B * column) + c, Real(0));
            }
        }
    };
    for (std::size_t i = 0; i < masses; ++i)
    {
        addBlock(i, i);
    }
    for (const SpringEnds& e : ends)
    {
        addBlock(e.a, e.b);
        addBlock(e.b, e.a);
    }
    SparseMatrix m(Eigen::Index(B * masses), Eigen::Index(B * masses));
    m.setFromTriplets(triplets.begin(), triplets.end());
    m.makeCompressed();
    return m;
}

template <int B> void expectPatternOfTriplets(std::size_t masses, const std::vector<SpringEnds>& ends)
{
    SlotMatrix<B> matrix;
    matrix.build(masses, ends);
    const SparseMatrix reference = patternFromTriplets<B>(masses, ends);
    const SparseMatrix& built = matrix.matrix();
    ASSERT_TRUE(built.isCompressed());
    ASSERT_EQ(built.rows(), reference.rows());
    ASSERT_EQ(built.nonZeros(), reference.nonZeros());
    for (Eigen::Index c = 0; c <= built.cols(); ++c)
    {
        EXPECT_EQ(built.outerIndexPtr()[c], reference.outerIndexPtr()[c]) << "column " << c;
    }
    for (Eigen::Index k = 0; k < built.nonZeros(); ++k)
    {
        EXPECT_EQ(built.innerIndexPtr()[k], reference.innerIndexPtr()[k]) << "entry " << k;
        EXPECT_EQ(built.valuePtr()[k], Real(0));
    }
}
} // namespace

// The pattern is written straight into the compressed arrays; it must be the one Eigen builds from the blocks'
// triplets, entry for entry: a spring listed twice, a spring from a mass to itself, a mass no spring reaches, springs
// given in no order.
TEST(SlotMatrix, PatternIsTheOneEigenBuildsFromTheBlocks)
{
    const std::vector<SpringEnds> ends = {{4, 1}, {0, 1}, {2, 3}, {1, 2}, {3, 3}, {2, 1}, {0, 4}, {5, 0}};
    expectPatternOfTriplets<1>(7, ends);
    expectPatternOfTriplets<3>(7, ends);
    expectPatternOfTriplets<3>(chainMasses, chainEnds);
    expectPatternOfTriplets<3>(3, {});
}

TEST(SlotMatrix, RefusesASpringToAMassItDoesNotHave)
{
    SlotMatrix<3> matrix;
    EXPECT_THROW(matrix.build(3, {{0, 1}, {1, 3}}), std::out_of_range);
}
