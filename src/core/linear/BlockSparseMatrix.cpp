#include "core/linear/BlockSparseMatrix.h"

#include <algorithm>

namespace masse
{
std::uint32_t BlockSparseMatrix::find(std::size_t row, std::uint32_t col) const
{
    const auto begin = column.begin() + rowStart[row];
    const auto end = column.begin() + rowStart[row + 1];
    return std::uint32_t(std::lower_bound(begin, end, col) - column.begin());
}

void multiplyBlockRows(const BlockSparseMatrix& a, const Eigen::VectorX<Real>& x, Eigen::VectorX<Real>& y,
                       std::size_t begin, std::size_t end)
{
    const std::uint32_t* start = a.rowStart.data();
    const std::uint32_t* column = a.column.data();
    const Mat3* block = a.block.data();
    const Real* in = x.data();
    for (std::size_t row = begin; row < end; ++row)
    {
        Vec3 sum = Vec3::Zero();
        for (std::uint32_t k = start[row]; k < start[row + 1]; ++k)
        {
            sum += block[k] * Eigen::Map<const Vec3>(in + 3 * std::size_t(column[k]));
        }
        y.segment<3>(Eigen::Index(3 * row)) = sum;
    }
}
} // namespace masse
