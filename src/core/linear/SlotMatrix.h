#pragma once
/// A sparse symmetric matrix over the masses of a sheet, with one B x B block per mass on the diagonal and one per
/// spring at (a, b) and at (b, a): the shape of every linear system the sheet's springs couple. The implicit
/// integrator's step uses 3x3 blocks (a velocity change per mass), the heat model scalars (a temperature per mass).
///
/// The pattern is built once from the spring ends; afterwards only values change, reached through slots recorded per
/// mass and per spring: for each of a block's B columns, the index in Eigen's value array of the block's top entry
/// (the block's other rows follow it in the column). Assembly writes straight into the compressed matrix and
/// allocates nothing.

#include "core/Types.h"
#include "core/lattice/SpringTopology.h"

#include <Eigen/SparseCore>

#include <algorithm>
#include <array>
#include <limits>
#include <vector>

namespace masse
{
using SparseMatrix = Eigen::SparseMatrix<Real>;

template <int B> class SlotMatrix
{
public:
    using StorageIndex = SparseMatrix::StorageIndex;
    /// Per column of a block, the value-array index of its top entry.
    using Slots = std::array<StorageIndex, B>;
    using Block = Eigen::Matrix<Real, B, B>;

    /// The most masses a matrix can hold: Eigen's index type must reach past the end of its value array.
    static constexpr std::size_t maxMasses() { return std::size_t(std::numeric_limits<StorageIndex>::max() / 4 / B); }

    /// Builds the pattern of `masses` masses joined by `ends`, every value zero. Throws InputError when there are more
    /// than maxMasses().
    void build(std::size_t masses, const std::vector<SpringEnds>& ends);
    /// The slots of the block in block row `row`, block column `column`: a mass's own or that of a spring joining the
    /// two. Throws std::out_of_range for any other block, which the pattern does not hold.
    Slots slotsOf(std::size_t row, std::size_t column) const;

    SparseMatrix& matrix() { return m_matrix; }
    const SparseMatrix& matrix() const { return m_matrix; }
    /// Mass i's block on the diagonal.
    const Slots& diagonal(std::size_t mass) const { return m_diagonal[mass]; }
    /// Spring s's block in row a (its first end), column b, and the transposed place.
    const Slots& ab(std::size_t spring) const { return m_ab[spring]; }
    const Slots& ba(std::size_t spring) const { return m_ba[spring]; }

    /// Every value to zero, the pattern kept.
    void setZero() { std::fill(m_matrix.valuePtr(), m_matrix.valuePtr() + m_matrix.nonZeros(), Real(0)); }

    Block read(const Slots& slots) const { return read(m_matrix, slots); }
    /// The block of `matrix` whose columns' top entries are at `slots` (its rows following them).
    static Block read(const SparseMatrix& matrix, const Slots& slots)
    {
        const Real* values = matrix.valuePtr();
        Block block;
        for (int c = 0; c < B; ++c)
        {
            const Real* column = values + slots[std::size_t(c)];
            for (int r = 0; r < B; ++r)
            {
                block(r, c) = column[r];
            }
        }
        return block;
    }
    void write(const Slots& slots, const Block& block)
    {
        Real* values = m_matrix.valuePtr();
        for (int c = 0; c < B; ++c)
        {
            Real* column = values + slots[std::size_t(c)];
            for (int r = 0; r < B; ++r)
            {
                column[r] = block(r, c);
            }
        }
    }
    void add(const Slots& slots, const Block& block)
    {
        Real* values = m_matrix.valuePtr();
        for (int c = 0; c < B; ++c)
        {
            Real* column = values + slots[std::size_t(c)];
            for (int r = 0; r < B; ++r)
            {
                column[r] += block(r, c);
            }
        }
    }
    /// The one value of a scalar block.
    Real& value(const Slots& slots) requires(B == 1) { return m_matrix.valuePtr()[slots[0]]; }

private:
    SparseMatrix m_matrix;
    std::vector<Slots> m_diagonal;
    std::vector<Slots> m_ab;
    std::vector<Slots> m_ba;
};

// Built for the two block sizes the engine uses (SlotMatrix.cpp).
extern template class SlotMatrix<1>;
extern template class SlotMatrix<3>;
} // namespace masse
