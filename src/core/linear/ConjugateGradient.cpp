#include "core/linear/ConjugateGradient.h"

#include "core/parallel/ChunkedSum.h"
#include "core/parallel/TaskPool.h"

#include <algorithm>
#include <cmath>

namespace masse
{
namespace
{
/// Rows per piece of a matrix-vector product: a task system hands out pieces of this many rows.
constexpr Eigen::Index productChunk = 3 * 1024;

void resizeIfNeeded(Vector& v, Eigen::Index size)
{
    if (v.size() != size)
    {
        v.resize(size);
    }
}

// Element-wise updates as plain loops: Eigen's packet code would use fused multiply-adds on a build that targets
// them, and the bits must not depend on the SIMD path.

/// y += alpha x over entries [begin, end).
void addScaled(Vector& y, Real alpha, const Vector& x, Eigen::Index begin, Eigen::Index end)
{
    for (Eigen::Index i = begin; i < end; ++i)
    {
        y[i] += alpha * x[i];
    }
}

/// p = z + beta p over entries [begin, end).
void updateDirection(Vector& p, const Vector& z, Real beta, Eigen::Index begin, Eigen::Index end)
{
    for (Eigen::Index i = begin; i < end; ++i)
    {
        p[i] = z[i] + beta * p[i];
    }
}

/// Whether rows `first` and `second` of `a` (its columns: the matrix is symmetric) have the same columns.
[[gnu::always_inline]] inline bool sameColumns(const SparseMatrix& a, Eigen::Index first, Eigen::Index second)
{
    const auto* outer = a.outerIndexPtr();
    const auto* inner = a.innerIndexPtr();
    return outer[first + 1] - outer[first] == outer[second + 1] - outer[second] &&
           std::equal(inner + outer[first], inner + outer[first + 1], inner + outer[second]);
}

/// y's rows `row` to `row + 2`, a mass's three rows sharing row `row`'s columns, summed together, each in its own
/// order as a row alone is: the three running sums do not wait on one another and each x is read once, and each row's
/// sum is the same as alone, bit for bit.
[[gnu::always_inline]] inline void multiplyMassRow(const SparseMatrix& a, const Real* in, Vector& y, Eigen::Index row)
{
    const auto* outer = a.outerIndexPtr();
    const auto count = outer[row + 1] - outer[row];
    const Real* v0 = a.valuePtr() + outer[row];
    const Real* v1 = a.valuePtr() + outer[row + 1];
    const Real* v2 = a.valuePtr() + outer[row + 2];
    const auto* columns = a.innerIndexPtr() + outer[row];
    Real sum0 = 0;
    Real sum1 = 0;
    Real sum2 = 0;
    for (std::ptrdiff_t k = 0; k < count; ++k)
    {
        const Real xk = in[columns[k]];
        sum0 += v0[k] * xk;
        sum1 += v1[k] * xk;
        sum2 += v2[k] * xk;
    }
    y[row] = sum0;
    y[row + 1] = sum1;
    y[row + 2] = sum2;
}
} // namespace

void multiplySymmetricRows(const SparseMatrix& a, const Vector& x, Vector& y, Eigen::Index begin, Eigen::Index end)
{
    const auto* outer = a.outerIndexPtr();
    const auto* inner = a.innerIndexPtr();
    const Real* values = a.valuePtr();
    const Real* in = x.data();
    Eigen::Index row = begin;
    while (row < end)
    {
        // A mass's three rows (the implicit matrix is in dense 3x3 blocks) share their columns.
        if (row + 2 < end && sameColumns(a, row, row + 1) && sameColumns(a, row, row + 2))
        {
            multiplyMassRow(a, in, y, row);
            row += 3;
            continue;
        }
        Real sum = 0;
        for (auto k = outer[row]; k < outer[row + 1]; ++k)
        {
            sum += values[k] * in[inner[k]];
        }
        y[row] = sum;
        ++row;
    }
}

void multiplyMassRows(const SparseMatrix& a, const Vector& x, Vector& y, Eigen::Index begin, Eigen::Index end,
                      const std::uint8_t* identityMasses)
{
    for (Eigen::Index row = begin; row < end; row += 3)
    {
        if (identityMasses && identityMasses[row / 3])
        {
            for (Eigen::Index r = row; r < row + 3; ++r)
            {
                y[r] = x[r] + Real(0); // -0 becomes +0, as in the sum
            }
            continue;
        }
        multiplyMassRow(a, x.data(), y, row);
    }
}

bool rowsComeInThrees(const SparseMatrix& a)
{
    if (a.rows() % 3 != 0)
    {
        return false;
    }
    for (Eigen::Index row = 0; row < a.rows(); row += 3)
    {
        if (!sameColumns(a, row, row + 1) || !sameColumns(a, row, row + 2))
        {
            return false;
        }
    }
    return true;
}

void ConjugateGradient::multiply(const SparseMatrix& a, const Vector& x, Vector& y) const
{
    static_assert(productChunk % 3 == 0, "a range of the product starts on a mass's first row");
    if (m_massRows)
    {
        const std::uint8_t* identity = m_identityMasses && Eigen::Index(m_identityMasses->size()) * 3 == a.rows()
                                           ? m_identityMasses->data()
                                           : nullptr;
        parallelFor(std::size_t(a.rows()), std::size_t(productChunk),
                    [&](std::size_t begin, std::size_t end)
                    { multiplyMassRows(a, x, y, Eigen::Index(begin), Eigen::Index(end), identity); });
        return;
    }
    parallelFor(std::size_t(a.rows()), std::size_t(productChunk),
                [&](std::size_t begin, std::size_t end)
                { multiplySymmetricRows(a, x, y, Eigen::Index(begin), Eigen::Index(end)); });
}

Real ConjugateGradient::dot(const Vector& u, const Vector& v)
{
    return chunkedDot(u, v);
}

SolveResult ConjugateGradient::solve(const SparseMatrix& a, const Vector& b, Vector& x,
                                     const Preconditioner& preconditioner, Real tolerance, int maxIterations,
                                     bool foresee)
{
    const Eigen::Index n = a.rows();
    resizeIfNeeded(m_residual, n);
    resizeIfNeeded(m_direction, n);
    resizeIfNeeded(m_preconditioned, n);
    resizeIfNeeded(m_product, n);
    SolveResult result;

    const Real rhsNorm2 = dot(b, b);
    if (rhsNorm2 == 0)
    {
        x.setZero();
        result.converged = true;
        return result;
    }
    if (!std::isfinite(rhsNorm2))
    {
        // A non-finite right-hand side (an infinite force) would meet the threshold of infinity at once and leave x
        // as it was: pass it through instead, so the simulator's finite check stops the run.
        x = b;
        return result;
    }
    const Real threshold = tolerance * tolerance * rhsNorm2;

    multiply(a, x, m_product);
    for (Eigen::Index k = 0; k < n; ++k)
    {
        m_residual[k] = b[k] - m_product[k];
    }
    Real residualNorm2 = dot(m_residual, m_residual);
    if (residualNorm2 <= threshold)
    {
        result.residual = std::sqrt(residualNorm2 / rhsNorm2);
        result.converged = true;
        return result;
    }
    preconditioner.apply(m_residual, m_direction);
    Real absNew = dot(m_residual, m_direction);
    const Real firstNorm2 = residualNorm2;
    int nextForecast = 16;
    int i = 0;
    while (i < maxIterations)
    {
        multiply(a, m_direction, m_product);
        const Real alpha = absNew / dot(m_direction, m_product);
        parallelFor(std::size_t(n), std::size_t(productChunk),
                    [&](std::size_t begin, std::size_t end)
                    {
                        addScaled(x, alpha, m_direction, Eigen::Index(begin), Eigen::Index(end));
                        addScaled(m_residual, -alpha, m_product, Eigen::Index(begin), Eigen::Index(end));
                    });
        residualNorm2 = dot(m_residual, m_residual);
        ++i;
        if (residualNorm2 <= threshold)
        {
            break;
        }
        if (foresee && i == nextForecast)
        {
            nextForecast *= 2;
            // Iterations still needed at the mean rate so far: log(threshold / r^2) / log(rate^2), with
            // rate^2 = (r^2 / r0^2)^(1 / i). A residual that has not fallen at all foretells nothing finite.
            const Real fallen = std::log(residualNorm2 / firstNorm2);
            const Real needed = std::log(threshold / residualNorm2);
            if (fallen < 0 && Real(i) * (needed / fallen) > Real(maxIterations - i))
            {
                result.foreseenShort = true;
                break;
            }
        }
        preconditioner.apply(m_residual, m_preconditioned);
        const Real absOld = absNew;
        absNew = dot(m_residual, m_preconditioned);
        const Real beta = absNew / absOld;
        parallelFor(std::size_t(n), std::size_t(productChunk),
                    [&](std::size_t begin, std::size_t end)
                    { updateDirection(m_direction, m_preconditioned, beta, Eigen::Index(begin), Eigen::Index(end)); });
    }
    result.iterations = i;
    result.residual = std::sqrt(residualNorm2 / rhsNorm2);
    result.converged = residualNorm2 <= threshold;
    return result;
}
} // namespace masse
