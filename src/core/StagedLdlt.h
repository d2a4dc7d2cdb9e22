#pragma once
/// A sparse LDL^T factorisation whose rows are computed over the nested dissection's stages on all cores, giving
/// Eigen's SimplicialLDLT factor (the same arithmetic; see below for the order of the top separator's sums).
///
/// The factorisation is up-looking, as Eigen's: row k of L comes from a sparse triangular solve with the rows above it
/// that k's elimination-tree subtree holds. The ranges of one dissection stage are separate subtrees (see
/// DissectionOrder), so their rows read and write disjoint columns of L and can be computed at once; each row's
/// arithmetic is the same whoever computes it, so the factor does not depend on the thread count. Eigen's
/// factorisation runs on one core and was most of a refresh (4.6 s of 5.4 at 128x2x128).
///
/// The last stage, the top separator, is one range: row by row it would run on one core, and its rows hold most of
/// the arithmetic (at 128x2x128, 765 rows and 1.4 G of the 5 G updates). Its rows' entries in the columns below it
/// depend only on those columns, so they are computed for all its rows at once; then each row's updates of the
/// separator's own entries (its column of the Schur complement), at once; then the separator's dense block, row by
/// row. Each entry of the separator's rows then sums the columns below first and the separator's own after. That is
/// Eigen's order wherever a row's topological order lists the columns below first, as it does on the lattices
/// (StagedLdlt.IsEigensFactorBitForBitAtAnyThreadCount); where it would not, the factor is Eigen's to rounding. Either
/// way it has the same bits at any thread count.

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
    /// One step of row k's sparse triangular solve, Eigen's: y_i (held at y[i - offset]) gives l_ki = y_i / d_i,
    /// appended to column i; column i's entries so far update y. Returns l_ki y_i, the step's part of the pivot.
    [[gnu::always_inline]] inline Real appendToColumn(StorageIndex i, StorageIndex k, Real* y, StorageIndex offset);
    /// The top separator's rows (see the file comment); false if a pivot is zero.
    bool factorTopStage();
    /// The top separator's pattern, after the elimination tree and L's column starts.
    void analyseTopStage();
    /// Row k's pattern in topological order, Eigen's way (an elimination-tree walk from each entry of A's column
    /// k): written to pattern[top, n), top returned. `mark` holds `visit` for the rows reached.
    StorageIndex rowPattern(StorageIndex k, long long visit, long long* mark, StorageIndex* pattern) const;

    SparseMatrix m_upper;                     ///< the matrix's upper triangle, as Eigen's factorisation reads it
    std::vector<StorageIndex> m_upperSources; ///< per value of m_upper, the permuted matrix's it copies
    SparseMatrix m_lower;
    Vector m_diagonal;
    std::vector<StorageIndex> m_parent;      ///< elimination tree: parent of each row, -1 for a root
    std::vector<StorageIndex> m_columnCount; ///< entries of each column of L so far
    std::vector<std::vector<OrderRange>> m_stages;
    long long m_generation = 0; ///< this factorisation's number in the process (tells its visit marks from others')

    /// The top separator's rows [begin, end) (none when begin == end) and their pattern, from analyse.
    struct TopStage
    {
        StorageIndex begin = 0;
        StorageIndex end = 0;
        std::vector<std::size_t> belowStart;     ///< per row and one past: its entries in the columns below begin
        std::vector<StorageIndex> belowColumn;   ///< those columns, in the row's topological order
        std::vector<StorageIndex> belowPosition; ///< where each entry goes in L's arrays
        std::vector<StorageIndex> belowCount;    ///< per column below begin: its entries in rows below begin
        std::vector<std::size_t> ownStart;       ///< per row and one past: its entries in the separator's columns
        std::vector<StorageIndex> ownColumn;     ///< those columns, in topological order
        // Per factorisation:
        std::vector<Real> belowY;       ///< per entry below: y_c = l_kc d_c, before the division
        std::vector<Real> partialPivot; ///< per row: a_kk - sum over the columns below of l_kc y_c
        std::vector<Real> schur;        ///< per row k, packed: a_jk - sum over the columns below of l_jc y_c, j < k
        std::vector<Real> row;          ///< the row being finished, over the separator
    };
    TopStage m_top;
};
} // namespace masse
