#pragma once
/// A sparse Cholesky factor (LDL^T) of a recent implicit-step matrix, used as the conjugate gradient's
/// preconditioner and refreshed only when it has drifted (the caller refactors when a solve needs more than a few
/// iterations). With a fresh factor the solve takes one or two iterations at any size and stiffness; as the sheet
/// turns and its stiffness changes the old factor stays a close, symmetric positive definite approximation.
///
/// Contact filters change from step to step, so the factor is applied through the current step's filter:
///     z = S F^-1 S r + (I - S) r
/// with S the per-mass projection onto the free directions. This is symmetric positive definite, and equals the
/// exact inverse of the filtered matrix S A S + I - S when F was factored from that matrix with the same filter.
///
/// Between refreshes the factor follows the current matrix's diagonal blocks (followDiagonal): much of what moves a
/// forming sheet's matrix from step to step belongs to single masses (a contact's friction damping, sized by its
/// press and slip every frame; a constraint gained; a mass's springs softened by heat), and a factor that ignores it
/// needs a refresh for it. With C_i and C'_i the Cholesky factors of mass i's 3x3 diagonal block in the factored and
/// in the current matrix, R = diag(C_i^-T C'_i^T) takes each factored block to the current one (R_i^T B_i R_i = B'_i),
/// and the preconditioner becomes S R^-1 F^-1 R^-T S r + (I - S) r: still symmetric positive definite, exact where
/// the matrix moved by scaling masses' rows and columns, and F's own where a block did not move. It keeps a mass's
/// couplings in proportion to its block, so where a large damping appears on a mass that had none it helps less
/// than where dampings are resized or move from mass to mass (CholeskyPreconditioner's test in
/// NestedDissectionTest.cpp measures both).

#include "core/linear/MassBlockRows.h"
#include "core/linear/NestedDissection.h"
#include "core/linear/RefreshedPreconditioner.h"
#include "core/linear/SlotMatrix.h"

#include "core/linear/StagedLdlt.h"

#include <Eigen/SparseCore>

#include <algorithm>
#include <vector>

namespace masse
{
class CholeskyPreconditioner final : public RefreshedPreconditioner
{
public:
    /// How deep the dissection's independent parts go (2^4 = 16 parts at most in stage 0): enough parts to share
    /// among threads however unevenly they take; a constant, so the ranges do not depend on the thread count.
    static constexpr int parallelDepth = 4;

    /// Analyses the matrix's pattern with the masses eliminated in `dissection.order` (see NestedDissection.h); once
    /// per topology. The matrix has three rows per mass.
    void analyse(const SparseMatrix& a, const DissectionOrder& dissection);
    /// Factors the matrix's current values (same pattern as analysed). Returns false if it is not positive definite.
    bool refresh(const SparseMatrix& a) override;
    bool ready() const override { return m_ready; }
    /// The masses filtered this step and their S (both outlive the solve); empty for none.
    void setFilter(const std::vector<Index>& masses, const std::vector<Mat3>& filters) override;
    void apply(const Vector& r, Vector& z) const override;
    /// Makes apply() follow `a`'s diagonal blocks (the analysed pattern; see above) until the next refresh. Returns
    /// false, following nothing, when a block is not positive definite.
    bool followDiagonal(const SparseMatrix& a);
    /// A refactorisation's updates per entry of the factor (StagedLdlt::updates over its entries), from the pattern.
    double updatesPerEntry() const
    {
        return m_factor.updates() / double(std::max<Eigen::Index>(m_factor.lower().nonZeros(), 1));
    }
    /// What a refresh costs, in conjugate gradient iterations with the factor, estimated from the pattern (so the same
    /// on every machine and at any thread count, as the refreshes it decides must be). A refresh takes some
    /// updatesPerEntry() applications of the factor; an iteration is an application, the product and the vector work.
    /// What an application costs depends on where the factor lives:
    /// - A factor that stays in the cache from one iteration to the next (up to cachedFactorValues; 64x2x64 has 3.4 M
    ///   values, 7 MB in half precision) costs an iteration as in masse_benchmarks' choleskyApply: 0.62 ms at 64x2x64,
    ///   where a refresh takes 31 ms and 125 updates an entry, some 0.4 iterations per update.
    /// - A factor past twice that streams from memory at every application: at 128x2x128 (17.7 M values, 35 MB) an
    ///   application takes 6.6 ms in the drape-forming run against 2.8 ms in choleskyApply/128, while a refresh takes
    ///   0.23 s and 214 updates an entry, some 0.16 iterations per update.
    /// - Between the two, the estimate goes linearly with the factor's size.
    /// Within a factor of two either way a refresh rule of this kind pays at most about twice the best schedule's cost
    /// (RefreshBudget), so the estimate needs no more precision than this: cachedCostPerUpdate and
    /// streamedCostPerUpdate are some 1.5 times those ratios, well within it.
    double refreshCost() const
    {
        const double streamed =
            std::clamp((double(m_factor.lower().nonZeros()) - cachedFactorValues) / cachedFactorValues, 0.0, 1.0);
        return (cachedCostPerUpdate - (cachedCostPerUpdate - streamedCostPerUpdate) * streamed) * updatesPerEntry();
    }
    /// Whether the backward solve asks for the factor's values ahead of its reads: where more values are live than
    /// cachedFactorValues, and the factor no longer stays in the cache from one application to the next.
    bool prefetchesFactor() const { return double(m_rows.liveEntries()) > cachedFactorValues; }
    /// Values of the factor up to which it counts as cached (see refreshCost); from twice as many, as streamed.
    static constexpr double cachedFactorValues = 8e6;
    /// Iterations a refresh is worth per update of an entry, for a cached factor and for a streamed one.
    static constexpr double cachedCostPerUpdate = 0.6;
    static constexpr double streamedCostPerUpdate = 0.27;
    /// Factorisations since construction.
    int refreshCount() const override { return m_refreshCount; }

private:
    void solveWithFactor(const Vector& b, Vector& x) const;

    using Permutation = Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, SparseMatrix::StorageIndex>;

    /// The factor of P A P^T (P: the nested dissection's order), factored over the dissection's stages.
    StagedLdlt m_factor;
    /// L by rows, a block of three rows a mass (see MassBlockRows), copied at each refresh for both triangular solves:
    /// the forward one gathers each block's rows, the backward one scatters each block's solved values into the rows
    /// above it, both running a stage's ranges on the pool (Eigen's forward solve scatters column by column into later
    /// rows, which two ranges' columns share, so it runs on one core; its backward solve walks the columns from the
    /// last down, jumping back a column at every column, which the memory prefetcher does not follow).
    MassBlockRows m_rows;
    /// Factor rows of each stage's ranges (see DissectionOrder::stages).
    std::vector<std::vector<OrderRange>> m_stages;
    Permutation m_permutation; ///< row i of A is row m_permutation.indices()[i] of the factored matrix
    SparseMatrix m_permutedMatrix;
    std::vector<SparseMatrix::StorageIndex> m_permutedSources; ///< per value of m_permutedMatrix, A's it copies
    const std::vector<Index>* m_masses = nullptr;
    const std::vector<Mat3>* m_filters = nullptr;
    mutable Vector m_filtered;
    mutable std::vector<float> m_permuted;    ///< the solves' work vector, in single precision (see solveWithFactor)
    mutable std::vector<float> m_scattered;   ///< the backward solve's sums of the solved rows' entries, per column
    mutable std::vector<Real> m_chunkLargest; ///< each chunk's largest entry of the solve's right-hand side
    std::vector<SlotMatrix<3>::Slots> m_diagonalSlots; ///< per mass, its diagonal block in the analysed pattern
    std::vector<Mat3> m_factoredBlocks; ///< per mass, C_i: the Cholesky factor of its block in the factored matrix
    std::vector<Mat3> m_following;      ///< per mass, R_i^-T = C_i C'_i^-1 (lower triangular), while m_followed
    bool m_canFollow = false;           ///< every mass's diagonal block is whole in the analysed pattern
    bool m_blocksFactored = false;      ///< m_factoredBlocks holds the last refresh's
    bool m_followed = false;
    bool m_ready = false;
    bool m_rowsLaidOut = false; ///< m_rows holds the runs of the analysed pattern
    int m_refreshCount = 0;
};
} // namespace masse
