#pragma once
/// Preconditioned conjugate gradient for the implicit step's symmetric positive definite matrix, with its work vectors
/// kept between solves (no allocation once sized) and every reduction summed in fixed chunks (ChunkedSum.h), so the
/// iterates are the same bit for bit however the kernels are shared among threads.
///
/// The stopping rule is Eigen's: |b - A x| <= tolerance |b|, so results compare with Eigen::ConjugateGradient's.

#include "core/Types.h"

#include <cstdint>
#include <vector>

#include <Eigen/SparseCore>

namespace masse
{
using SparseMatrix = Eigen::SparseMatrix<Real>;
using Vector = Eigen::VectorX<Real>;

/// z = P^-1 r for a symmetric positive definite P close to the matrix.
class Preconditioner
{
public:
    virtual ~Preconditioner() = default;
    virtual void apply(const Vector& r, Vector& z) const = 0;
};

/// What one solve did.
struct SolveResult
{
    int iterations = 0;
    Real residual = 0; ///< |b - A x| / |b| at the end
    bool converged = false;
    /// Stopped short of maxIterations because its rate so far foretold that it would not converge within them
    /// (solve's `foresee`).
    bool foreseenShort = false;
};

/// y = A x for a symmetric A stored by columns, computed row by row over rows [begin, end): column j of a symmetric
/// matrix is its row j, so each output entry is a gather and row ranges are independent.
void multiplySymmetricRows(const SparseMatrix& a, const Vector& x, Vector& y, Eigen::Index begin, Eigen::Index end);
/// The same product, bit for bit, for a matrix whose rows come in threes sharing their columns (a mass's three rows in
/// the implicit matrix's 3x3 blocks): multiplySymmetricRows compares each mass's three rows' columns before summing
/// them together, which reads the column indices three times over. `begin` and `end` are multiples of three.
/// `identityMasses`, if not null, marks per mass whether its three rows are the identity's (a one on the diagonal,
/// zeros elsewhere, as a pinned or held mass's rows of the implicit matrix are): their entries are x's own plus +0,
/// which is what the sum over the row gives (a sum from +0 never ends at -0) for a finite x.
void multiplyMassRows(const SparseMatrix& a, const Vector& x, Vector& y, Eigen::Index begin, Eigen::Index end,
                      const std::uint8_t* identityMasses = nullptr);
/// Whether every three rows of `a` from the first share their columns, as multiplyMassRows needs.
bool rowsComeInThrees(const SparseMatrix& a);

class ConjugateGradient
{
public:
    /// Improves x (the first guess) until the stopping rule holds or maxIterations have run. With `foresee`, it also
    /// stops at iteration 16, 32, 64, ... if the residual's mean rate of fall so far would take it past maxIterations
    /// (SolveResult::foreseenShort): a caller that would rebuild the preconditioner when the solve runs out of
    /// iterations (ImplicitSolve's refresh budget) learns it a hundred iterations sooner where the old preconditioner
    /// no longer fits at all (the plug-assist cup's stroke, where the friction under the plug changes the matrix
    /// every frame).
    SolveResult solve(const SparseMatrix& a, const Vector& b, Vector& x, const Preconditioner& preconditioner,
                      Real tolerance, int maxIterations, bool foresee = false);

    /// Whether the matrices solved have their rows in threes sharing their columns (rowsComeInThrees, for
    /// multiplyMassRows); false by default, and the product then finds the threes itself.
    void setMassRows(bool massRows) { m_massRows = massRows; }
    /// Per mass, whether its three rows of the matrices solved are the identity's (see multiplyMassRows; only with
    /// mass rows); null for none. The caller keeps it up to date for each solve, and it outlives them.
    void setIdentityMasses(const std::vector<std::uint8_t>* identityMasses) { m_identityMasses = identityMasses; }

private:
    void multiply(const SparseMatrix& a, const Vector& x, Vector& y) const;
    Real dot(const Vector& u, const Vector& v);

    Vector m_residual;
    Vector m_direction;
    Vector m_preconditioned;
    Vector m_product;
    bool m_massRows = false;
    const std::vector<std::uint8_t>* m_identityMasses = nullptr;
};
} // namespace masse
