#pragma once
/// A sparse LDL^T factorisation whose rows are computed over the nested dissection's stages on all cores, giving
/// exactly Eigen's SimplicialLDLT factor (the same arithmetic, row by row, in the same order).
///
/// The factorisation is up-looking, as Eigen's: row k of L comes from a sparse triangular solve with the rows above it
/// that k's elimination-tree subtree holds. The ranges of one dissection stage are separate subtrees (see
/// DissectionOrder), so their rows read and write disjoint columns of L and can be computed at once; each row's
/// arithmetic is the same whoever computes it, so the factor does not depend on the thread count. Eigen's
/// factorisation runs on one core and was most of a refresh (4.6 s of 5.4 at 128x2x128).

#include "NestedDissection.h"
#include "Types.h"

#include <Eigen/SparseCore>

#include <vector>

namespace masse
{
class StagedLdlt
{
public:
    using SparseMatrix = Eigen::SparseMatrix<Real>;
    using Vector = Eigen::VectorX<Real>;
    using StorageIndex = SparseMatrix::StorageIndex;

    /// The elimination tree and L's pattern of `permuted` (a symmetric matrix stored in full, already in elimination
    /// order), whose rows `stages` split as DissectionOrder::stages does (in rows, not masses).
    void analyse(const SparseMatrix& permuted, const std::vector<std::vector<OrderRange>>& stages);
    /// Factors `permuted` (the analysed pattern); false if a pivot is zero.
    bool factorize(const SparseMatrix& permuted);

    /// L's strictly lower part, column-major, each column's rows increasing (unit diagonal not stored).
    const SparseMatrix& lower() const { return m_lower; }
    const Vector& diagonal() const { return m_diagonal; }

private:
    /// m_upper = the upper triangle of `permuted` (stored in full).
    void assignUpper(const SparseMatrix& permuted);
    /// Rows [begin, end) of L and D; false if a pivot is zero.
    bool factorRows(StorageIndex begin, StorageIndex end);

    SparseMatrix m_upper; ///< the matrix's upper triangle, as Eigen's factorisation reads it
    SparseMatrix m_lower;
    Vector m_diagonal;
    std::vector<StorageIndex> m_parent;      ///< elimination tree: parent of each row, -1 for a root
    std::vector<StorageIndex> m_columnCount; ///< entries of each column of L so far
    std::vector<std::vector<OrderRange>> m_stages;
    long long m_generation = 0; ///< this factorisation's number in the process (tells its visit marks from others')
};
} // namespace masse
