#pragma once
/// The diagonal preconditioner (what Eigen's conjugate gradient uses by default): cheap, but the iteration count
/// grows with the sheet's size and stiffness. Kept as the reference the Cholesky preconditioner is measured against.

#include "core/linear/ConjugateGradient.h"

namespace masse
{
class JacobiPreconditioner final : public Preconditioner
{
public:
    /// Takes the inverse diagonal of the current matrix values.
    void refresh(const SparseMatrix& a)
    {
        if (m_inverseDiagonal.size() != a.rows())
        {
            m_inverseDiagonal.resize(a.rows());
        }
        for (Eigen::Index j = 0; j < a.outerSize(); ++j)
        {
            Real d = 0;
            for (SparseMatrix::InnerIterator it(a, j); it; ++it)
            {
                if (it.row() == j)
                {
                    d = it.value();
                }
            }
            m_inverseDiagonal[j] = d != 0 ? Real(1) / d : Real(1);
        }
    }

    void apply(const Vector& r, Vector& z) const override
    {
        for (Eigen::Index i = 0; i < r.size(); ++i)
        {
            z[i] = m_inverseDiagonal[i] * r[i];
        }
    }

private:
    Vector m_inverseDiagonal;
};
} // namespace masse
