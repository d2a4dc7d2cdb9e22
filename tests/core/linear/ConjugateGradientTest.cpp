// The conjugate gradient's foresight (ConjugateGradient::solve with `foresee`): a solve whose residual falls too slowly
// to converge within its iterations stops at a forecast point and says so; one that would converge is not stopped, and
// runs exactly as without foresight.

#include "core/linear/ConjugateGradient.h"
#include "core/linear/JacobiPreconditioner.h"

#include <Eigen/SparseCholesky>
#include <gtest/gtest.h>

#include <vector>

using namespace masse;

namespace
{
/// A chain of n unit masses joined by springs of stiffness k, its ends held by springs to the ground: M + K, whose
/// condition grows as k n^2. The diagonal preconditioner needs some n iterations on it.
SparseMatrix chainMatrix(Eigen::Index n, Real k)
{
    std::vector<Eigen::Triplet<Real>> triplets;
    for (Eigen::Index i = 0; i < n; ++i)
    {
        triplets.emplace_back(i, i, Real(1) + 2 * k);
        if (i + 1 < n)
        {
            triplets.emplace_back(i, i + 1, -k);
            triplets.emplace_back(i + 1, i, -k);
        }
    }
    SparseMatrix a(n, n);
    a.setFromTriplets(triplets.begin(), triplets.end());
    a.makeCompressed();
    return a;
}

/// The exact inverse, through Eigen's sparse Cholesky factor.
class ExactPreconditioner final : public Preconditioner
{
public:
    explicit ExactPreconditioner(const SparseMatrix& a) : m_factor(a) {}
    void apply(const Vector& r, Vector& z) const override { z = m_factor.solve(r); }

private:
    Eigen::SimplicialLDLT<SparseMatrix> m_factor;
};
} // namespace

TEST(ConjugateGradient, ForeseesASolveThatWillNotConvergeInTime)
{
    const Eigen::Index n = 2000;
    const SparseMatrix a = chainMatrix(n, 1e4);
    Vector b(n);
    for (Eigen::Index i = 0; i < n; ++i)
    {
        b[i] = Real((i * 37) % 101) / 101 - Real(0.5);
    }
    JacobiPreconditioner jacobi;
    jacobi.refresh(a);
    ConjugateGradient cg;

    // 100 iterations of the diagonal preconditioner are far too few: without foresight it takes all of them, with it
    // it stops at the first forecast point (iteration 16), not converged.
    Vector blind = Vector::Zero(n);
    const SolveResult all = cg.solve(a, b, blind, jacobi, 1e-8, 100);
    EXPECT_EQ(all.iterations, 100);
    EXPECT_FALSE(all.converged);
    EXPECT_FALSE(all.foreseenShort);
    Vector foreseeing = Vector::Zero(n);
    const SolveResult stopped = cg.solve(a, b, foreseeing, jacobi, 1e-8, 100, true);
    EXPECT_TRUE(stopped.foreseenShort);
    EXPECT_FALSE(stopped.converged);
    EXPECT_EQ(stopped.iterations, 16);

    // Given the iterations it needs, the solve is not stopped, and its iterates are those of the solve without
    // foresight, bit for bit.
    Vector x = Vector::Zero(n);
    const SolveResult plain = cg.solve(a, b, x, jacobi, 1e-8, 100000);
    ASSERT_TRUE(plain.converged);
    Vector y = Vector::Zero(n);
    const SolveResult foreseen = cg.solve(a, b, y, jacobi, 1e-8, 100000, true);
    EXPECT_TRUE(foreseen.converged);
    EXPECT_FALSE(foreseen.foreseenShort);
    EXPECT_EQ(foreseen.iterations, plain.iterations);
    EXPECT_TRUE((x.array() == y.array()).all());

    // A preconditioner that fits converges at once, with or without foresight.
    const ExactPreconditioner exact(a);
    Vector z = Vector::Zero(n);
    const SolveResult fitted = cg.solve(a, b, z, exact, 1e-8, 10, true);
    EXPECT_TRUE(fitted.converged);
    EXPECT_LE(fitted.iterations, 2);
    EXPECT_FALSE(fitted.foreseenShort);
}
