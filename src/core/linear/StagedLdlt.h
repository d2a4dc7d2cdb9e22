#pragma once
/// A sparse LDL^T factorisation whose rows are computed over the nested dissection's stages on all cores, giving
/// Eigen's SimplicialLDLT factor to rounding.
///
/// The factorisation is up-looking, as Eigen's: row k of L comes from a sparse triangular solve with the rows above it
/// that k's elimination-tree subtree holds. The ranges of one dissection stage are separate subtrees (see
/// DissectionOrder), so their rows read and write disjoint columns of L and can be computed at once.
///
/// The first stage's ranges (the dissection's parts) are factored a mass at a time: the three rows of a mass share
/// their columns below its block (the implicit matrix's 3x3 blocks give them that), so each of those columns is read
/// once and updates the three rows' y in one vector operation, in row k0's topological order; the mass's own block
/// follows as Eigen's rows would finish it. Rows without that structure are factored one by one with Eigen's
/// arithmetic. The same blocks give an earlier mass's three columns the same rows below its block, and they come
/// together in that order: they are taken together, each row's y read and written once for the three (see
/// m_columnsShareRows).
///
/// The later stages' ranges are separators, whose rows hold most of the arithmetic (at 128x2x128 the top one alone,
/// 765 rows, 1.4 G of the 5 G updates): row by row, each row would stream all the columns below it from memory again.
/// A separator's rows' entries in the columns below it depend only on those columns, so they are computed for `lanes`
/// rows at once, each column's entries read once for the block and applied to its rows in one vector operation (step
/// 1); then each row's updates of the separator's own entries (its column of the Schur complement), the same way (step
/// 2); then the separator's own block, whose Schur complement is nearly dense: factored as a dense matrix,
/// right-looking, each column's update of the later ones one vector operation over their entries (step 3), and its
/// pattern's entries written to L. Each entry of a separator's rows sums the columns below in increasing order, and its
/// own block's columns in increasing order. Where consecutive columns below have the same rows (every mass's three,
/// from the implicit matrix's 3x3 blocks, and longer runs among the separators' columns), steps 1 and 2 take up to
/// mostTogether of them together: each row's y is then read and written once for the run rather than once a column,
/// which is most of what those steps move through memory, and the run's subtractions keep their order, so the bits
/// stay the same.
///
/// A column whose y is zero in every row being factored (one of a held mass's, whose rows and columns of the filtered
/// matrix are the identity's, or one whose fill the held masses cut off) gives those rows zero entries and updates
/// nothing: its updates, which would subtract zeros, are left out, in the parts and in steps 1 and 2, as the dense
/// factorisation leaves out a column's zero entries. A formed sheet held on its mould is mostly such columns.
///
/// The factor is computed in single precision (Value) from the double-precision matrix. It only preconditions the
/// conjugate gradient, which converges in double precision whatever the preconditioner's rounding, and its solves
/// keep it in half precision (MassBlockRows.h): single precision's rounding, some 1e-6 of an entry at 24x2x24, is
/// far below the half values' 5e-4, and the forming runs take the same conjugate gradient iterations a step to within
/// 0.5%. Single values halve what the factorisation moves through memory, which is what bounds it: each row's y and
/// the columns' values.
///
/// These orders differ from Eigen's (each row's own topological one), so a value may differ from Eigen's single
/// precision factor in its last bits; they are fixed by the analysis, so the factor has the same bits at any thread
/// count and on any SIMD path (StagedLdlt.IsEigensFactorToRoundingWithTheSameBitsAtAnyThreadCount).

#include "core/Types.h"
#include "core/linear/NestedDissection.h"

#include <Eigen/SparseCore>

#include <algorithm>
#include <vector>

namespace masse
{
class StagedLdlt
{
public:
    using SparseMatrix = Eigen::SparseMatrix<Real>;
    using StorageIndex = SparseMatrix::StorageIndex;
    /// The factor's values: single precision (see above).
    using Value = float;
    using FactorMatrix = Eigen::SparseMatrix<Value>;
    using FactorVector = Eigen::VectorX<Value>;
    /// A separator's rows taken at once in the steps over its columns below (one AVX-512 register of Values).
    static constexpr std::size_t lanes = 16;

    /// The elimination tree and L's pattern of `permuted` (a symmetric matrix stored in full, already in elimination
    /// order), whose rows `stages` split as DissectionOrder::stages does (in rows, not masses).
    void analyse(const SparseMatrix& permuted, const std::vector<std::vector<OrderRange>>& stages);
    /// Factors `permuted` (the analysed pattern); false if a pivot is zero or not finite in single precision.
    bool factorize(const SparseMatrix& permuted);

    /// L's strictly lower part, column-major, each column's rows increasing (unit diagonal not stored).
    const FactorMatrix& lower() const { return m_lower; }
    const FactorVector& diagonal() const { return m_diagonal; }
    /// The multiply-adds of a factorisation, from the analysed pattern: a column's entries update each other's rows,
    /// sum over the columns of count (count - 1) / 2.
    double updates() const { return m_updates; }
    /// The most columns the separators' steps take together (see Blocks::together): each one's y for the block's
    /// rows stays in a register through the run (half of AVX-512's 32).
    static constexpr std::size_t mostTogether = 16;
    /// The separators' block entries taken together with others (see Blocks::together), from the analysis.
    std::size_t columnsTakenTogether() const
    {
        std::size_t taken = 0;
        for (const unsigned char width : m_blocks.together)
        {
            taken += width > 1 ? width : 0;
        }
        return m_takeTogether ? taken : 0;
    }
    /// The masses whose three columns have the same rows below their block, taken together by later masses of the
    /// parts (see m_columnsShareRows), from the analysis.
    std::size_t massesSharingRows() const
    {
        return m_takeTogether ? std::size_t(std::count(m_columnsShareRows.begin(), m_columnsShareRows.end(), 1)) : 0;
    }
    /// Whether the factorisations take such columns together (the default) or one by one; the factor has the same
    /// bits either way.
    void takeColumnsTogether(bool take) { m_takeTogether = take; }
    /// The masses (rows 3m to 3m + 2) the analysis found can be factored a mass at a time (see m_massTogether).
    std::size_t massesFactoredTogether() const
    {
        return std::size_t(std::count(m_massTogether.begin(), m_massTogether.end(), char(1)));
    }

private:
    /// m_upper = the upper triangle of `permuted` (stored in full).
    void assignUpper(const SparseMatrix& permuted);
    /// Rows [begin, end) of L and D; false if a pivot is zero.
    bool factorRows(StorageIndex begin, StorageIndex end);
    /// One step of row k's sparse triangular solve, Eigen's: y_i gives l_ki = y_i / d_i, appended to column i; column
    /// i's entries so far update y. Returns l_ki y_i, the step's part of the pivot.
    [[gnu::always_inline]] inline Value appendToColumn(StorageIndex i, StorageIndex k, Value* y);
    /// Rows k0, k0 + 1 and k0 + 2 of L and D, one mass's, at once (see m_massTogether): each column below the mass's
    /// block is read once for the three rows, whose scattered y are `massY` (four values a row, all zero between
    /// masses: every value scattered is in a column of the mass's pattern, and each column is cleared as it is taken,
    /// so it is all zero again on return, a refused pivot included). False if a pivot is zero.
    bool factorMass(StorageIndex k0, Value* massY, long long visit, long long* mark, StorageIndex* pattern);
    /// Which masses factorMass can take (m_massTogether), after the elimination tree and L's column starts.
    void analyseMasses();
    /// The separators of stage `stage` (see the file comment); false if a pivot is zero.
    bool factorSeparators(std::size_t stage);
    /// The separators' patterns and blocks, after the elimination tree and L's column starts; `separatorEntries` holds
    /// each column's entries in the separators' rows.
    void analyseSeparators(const std::vector<StorageIndex>& separatorEntries);
    /// Row k's pattern in topological order, Eigen's way (an elimination-tree walk from each entry of A's column
    /// k): written to pattern[top, n), top returned. `mark` holds `visit` for the rows reached.
    StorageIndex rowPattern(StorageIndex k, long long visit, long long* mark, StorageIndex* pattern) const;

    SparseMatrix m_upper;                     ///< the matrix's upper triangle, as Eigen's factorisation reads it
    std::vector<StorageIndex> m_upperSources; ///< per value of m_upper, the permuted matrix's it copies
    FactorMatrix m_lower;
    FactorVector m_diagonal;
    std::vector<StorageIndex> m_parent;      ///< elimination tree: parent of each row, -1 for a root
    std::vector<StorageIndex> m_columnCount; ///< entries of each column of L so far
    std::vector<std::vector<OrderRange>> m_stages;
    /// Per mass (rows 3m to 3m + 2): whether its rows lie in one range of the first stage, hold their 3x3 block in
    /// full and have the same columns below it (the implicit matrix's 3x3 blocks give that to every mass); such a
    /// mass's rows are factored together.
    std::vector<char> m_massTogether;
    /// Per mass: whether its three columns have the same rows below its block (column 3m's first two entries in rows
    /// 3m + 1 and 3m + 2, column 3m + 1's first in row 3m + 2); the factorisation of a later mass takes such columns
    /// together where they come together, as the separators' steps do (see Blocks::together).
    std::vector<unsigned char> m_columnsShareRows;
    double m_updates = 0;
    long long m_generation = 0; ///< this factorisation's number in the process (tells its visit marks from others')

    /// A separator: a range of a stage after the first, rows [begin, end), with its pattern from analyse.
    struct Separator
    {
        StorageIndex begin = 0;
        StorageIndex end = 0;
        std::size_t firstBlock = 0; ///< its blocks of rows (see Blocks): [firstBlock, endBlock)
        std::size_t endBlock = 0;
        std::vector<std::size_t> ownColumnStart; ///< per column of the separator and one past: its rows in it
        std::vector<StorageIndex> ownColumnRows; ///< those rows, increasing
        // Per factorisation:
        std::vector<Value> partialPivot; ///< per row: a_kk - sum over the columns below of l_kc y_c
        std::vector<Value> schur;        ///< per row k, packed: a_jk - sum over the columns below of l_jc y_c, j < k
    };
    std::vector<Separator> m_separators;
    std::vector<std::size_t> m_stageSeparators; ///< per stage and one past: its first separator (none in stage 0)
    std::vector<std::vector<std::size_t>> m_stageBlocks; ///< per stage: its separators' blocks

    /// The separators' rows, `lanes` at a time (each separator's from its first row, the last block of each maybe
    /// short), for the steps over the columns below. Per block and one past, its entries; per entry, a column below
    /// its separator that one of the block's rows has (a block's columns in increasing order), which rows have it
    /// (bit r for the block's r-th row), where each such row's entry goes in L's arrays (`lanes` slots an entry, -1
    /// where the row has none), and where the column's entries in rows below the separator and in its rows end.
    struct Blocks
    {
        std::vector<std::size_t> separator; ///< per block
        std::vector<StorageIndex> firstRow; ///< per block
        std::vector<std::size_t> start;
        std::vector<StorageIndex> column;
        std::vector<unsigned> rows;
        std::vector<StorageIndex> position;
        std::vector<StorageIndex> belowEnd;
        std::vector<StorageIndex> separatorEnd;
        /// Per entry: how many columns from it, at most mostTogether, are taken together (0 inside such a run): a
        /// run of consecutive columns, each the next one's child in the elimination tree with one row more, so with
        /// the same rows below the run, below the separator and in it (a mass's three columns at least, from the
        /// implicit matrix's 3x3 blocks; the separators' own columns come in longer runs). The steps take such
        /// columns together: each row's y is read and written once for the run, and its columns subtract from it in
        /// the same order as column by column, so with the same bits.
        std::vector<unsigned char> together;
        // Per factorisation:
        std::vector<Value> y; ///< per entry and row: y_c = l_kc d_c, before the division (0 where the row has none)
    };
    /// Whether column j has column j + 1's rows below j + 1, and those alone: j is j + 1's child in the elimination
    /// tree with one row more (j + 1 must be a column).
    bool sharesRowsWithNext(std::size_t j) const;
    /// How many of a block's columns from entry e, up to blockEnd, are taken together (see Blocks::together).
    std::size_t runFrom(std::size_t e, std::size_t blockEnd) const;
    Blocks m_blocks;
    bool m_takeTogether = true;
    /// All zero: read for the flags of the columns taken together while takeColumnsTogether(false) holds.
    std::vector<unsigned char> m_notTogether;
};
} // namespace masse
