#pragma once
/// An algebraic multigrid V-cycle over the sheet's aggregates (Aggregation.h), used as the conjugate gradient's
/// preconditioner: each level's operator is the Galerkin product P^T A P of the finer one, built from a recent matrix
/// and rebuilt only when it has drifted (as the Cholesky factor is); each level but the coarsest is smoothed by a
/// Chebyshev polynomial in its block-diagonal (per node 3x3) scaling, and the coarsest is factored (LDL^T).
///
/// Every kernel of a cycle (the smoothing sweeps, residuals, restriction and interpolation) is a gather over node
/// ranges on the task pool, so a cycle's bits do not depend on the thread count; its cost is a few products with
/// the fine matrix, where a factor's two triangular solves stream a factor many times the matrix's size (25.8 M
/// nonzeros against 2.9 M at 128x2x128) and its refactorisation takes seconds.
///
/// Contact filters: the fine level is built with the filter of the step it is refreshed at (its interpolation is S P,
/// so a coarse motion never moves a mass along a direction it is held in, and a pinned or wholly held mass not at
/// all), and applied through the current step's as z = S M^-1 S r + (I - S) r, which stays symmetric positive
/// definite.

#include "core/linear/Aggregation.h"
#include "core/linear/BlockSparseMatrix.h"
#include "core/linear/RefreshedPreconditioner.h"

#include <Eigen/SparseCholesky>

#include <cstdint>
#include <vector>

namespace masse
{
class MultigridPreconditioner final : public RefreshedPreconditioner
{
public:
    /// Levels are coarsened until at most this many nodes are left; the coarsest is factored.
    static constexpr std::size_t coarsestNodes = 600;
    /// Degree of the Chebyshev smoother, before and after the coarse correction.
    static constexpr int smoothingDegree = 2;
    /// The smoother damps the part of each level's spectrum above lambda_max / this.
    static constexpr Real smoothedRange = 30;

    /// Builds the levels' patterns and interpolations (once per topology) for a matrix with three rows per mass.
    void analyse(const SparseMatrix& a, const SpringSet& springs, std::size_t masses);
    bool refresh(const SparseMatrix& a) override;
    bool ready() const override { return m_ready; }
    void setFilter(const std::vector<Index>& masses, const std::vector<Mat3>& filters) override;
    void apply(const Vector& r, Vector& z) const override;
    int refreshCount() const override { return m_refreshCount; }
    std::size_t levelCount() const { return m_levels.size(); }

private:
    struct Level
    {
        BlockSparseMatrix matrix;
        std::vector<Mat3> inverseDiagonal;
        Real largestEigenvalue = 1; ///< of D^-1 A, from a power iteration, with a margin
        /// Each node's aggregate on the next level (empty on the coarsest).
        std::vector<std::uint32_t> aggregateOf;
        BlockSparseMatrix interpolation; ///< P, from the next level to this one (empty on the coarsest)
        BlockSparseMatrix restriction;   ///< P^T
        /// For each block of the restriction, the interpolation block it is the transpose of.
        std::vector<std::uint32_t> transposeOf;
        BlockSparseMatrix product; ///< A P, for the next level's Galerkin product
        // Work vectors of a cycle, three entries per node.
        mutable Vector rhs;
        mutable Vector x;
        mutable Vector xNext;
        mutable Vector direction;
        mutable Vector residual;
    };

    void copyFineMatrix(const SparseMatrix& a);
    void smoothInterpolation(std::size_t level);
    void galerkin(std::size_t level);
    void invertDiagonal(std::size_t level);
    void estimateLargestEigenvalue(std::size_t level);
    bool factorCoarsest();

    void cycle(std::size_t level) const;
    /// smoothingDegree Chebyshev steps on level's x (from zero when `fromZero`).
    void smooth(std::size_t level, bool fromZero) const;
    void solveCoarsest() const;

    std::vector<Level> m_levels;
    /// Level 0's block k, row r: the value-array position of the scalar matrix's entry (3 col + r, 3 row), the top
    /// of the block's row r in a column of the symmetric CSC (whose column 3 i + r is its row 3 i + r).
    std::vector<std::array<SparseMatrix::StorageIndex, 3>> m_fineSlots;
    /// Level 0's per-mass S at the last refresh (identity, the contact filter's, or zero for a mass the matrix
    /// leaves decoupled: pinned, or held in all directions); only masses with m_fineFiltered set are not identity.
    std::vector<Mat3> m_fineFilter;
    std::vector<std::uint8_t> m_fineFiltered;

    Eigen::SimplicialLDLT<SparseMatrix> m_coarsest;
    SparseMatrix m_coarsestMatrix;
    Vector m_coarsestDiagonal;
    mutable Vector m_coarsestPermuted;

    const std::vector<Index>* m_masses = nullptr;
    const std::vector<Mat3>* m_filters = nullptr;
    bool m_ready = false;
    int m_refreshCount = 0;
};
} // namespace masse
