#pragma once
/// A sparse matrix of 3x3 blocks stored by block rows (block CSR): the operators of the multigrid's levels, one block
/// row per mass or per coarse node. One column index per nine values (the scalar CSC the implicit step assembles has
/// one per value), and a row's product is a gather in a fixed order, so rows can be shared among threads and the bits
/// do not depend on how.

#include "core/Types.h"

#include <Eigen/Core>

#include <cstdint>
#include <vector>

namespace masse
{
struct BlockSparseMatrix
{
    /// Blocks of block row i: [rowStart[i], rowStart[i + 1]), columns ascending.
    std::vector<std::uint32_t> rowStart;
    std::vector<std::uint32_t> column;
    std::vector<Mat3> block;

    std::size_t rows() const { return rowStart.empty() ? 0 : rowStart.size() - 1; }
    /// The position of block (row, col) in `block`; the block must be in the pattern.
    std::uint32_t find(std::size_t row, std::uint32_t col) const;
};

/// y = A x over block rows [begin, end) (x and y hold three entries per block row).
void multiplyBlockRows(const BlockSparseMatrix& a, const Eigen::VectorX<Real>& x, Eigen::VectorX<Real>& y,
                       std::size_t begin, std::size_t end);
} // namespace masse
