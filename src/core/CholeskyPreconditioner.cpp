#include "CholeskyPreconditioner.h"

namespace masse
{
void CholeskyPreconditioner::analyse(const SparseMatrix& a, const std::vector<Index>& massOrder)
{
    m_permutation.resize(a.rows());
    for (std::size_t position = 0; position < massOrder.size(); ++position)
    {
        for (int c = 0; c < 3; ++c)
        {
            m_permutation.indices()[Eigen::Index(3 * massOrder[position]) + c] =
                SparseMatrix::StorageIndex(3 * position) + c;
        }
    }
    m_permutedMatrix = a.selfadjointView<Eigen::Lower>().twistedBy(m_permutation);
    m_factor.analyzePattern(m_permutedMatrix);
    m_ready = false;
    m_filtered.resize(a.rows());
    m_permuted.resize(a.rows());
}

bool CholeskyPreconditioner::refresh(const SparseMatrix& a)
{
    // A refresh (not every step) copies the matrix into the factor's order; the pattern is unchanged.
    m_permutedMatrix = a.selfadjointView<Eigen::Lower>().twistedBy(m_permutation);
    m_factor.factorize(m_permutedMatrix);
    m_ready = m_factor.info() == Eigen::Success;
    ++m_refreshCount;
    return m_ready;
}

void CholeskyPreconditioner::setFilter(const std::vector<Index>& masses, const std::vector<Mat3>& filters)
{
    m_masses = &masses;
    m_filters = &filters;
}

void CholeskyPreconditioner::apply(const Vector& r, Vector& z) const
{
    const bool filtered = m_masses && !m_masses->empty();
    const Vector* input = &r;
    if (filtered)
    {
        m_filtered = r;
        for (std::size_t k = 0; k < m_masses->size(); ++k)
        {
            const Eigen::Index row = Eigen::Index(3 * (*m_masses)[k]);
            m_filtered.segment<3>(row) = (*m_filters)[k] * r.segment<3>(row);
        }
        input = &m_filtered;
    }
    solveWithFactor(*input, z);
    if (filtered)
    {
        for (std::size_t k = 0; k < m_masses->size(); ++k)
        {
            const Eigen::Index row = Eigen::Index(3 * (*m_masses)[k]);
            const Mat3& s = (*m_filters)[k];
            const Vec3 free = s * z.segment<3>(row);
            z.segment<3>(row) = free + (r.segment<3>(row) - s * r.segment<3>(row));
        }
    }
}

void CholeskyPreconditioner::solveWithFactor(const Vector& b, Vector& x) const
{
    // P^T L D L^T P x = b, spelled out rather than through SimplicialLDLT::solve, whose in-place permutation
    // allocates a mask on every call.
    const auto& permutation = m_permutation.indices();
    const Eigen::Index n = b.size();
    for (Eigen::Index i = 0; i < n; ++i)
    {
        m_permuted[permutation[i]] = b[i];
    }
    m_factor.matrixL().solveInPlace(m_permuted);
    const Vector& d = m_factor.vectorD();
    for (Eigen::Index i = 0; i < n; ++i)
    {
        m_permuted[i] /= d[i];
    }
    m_factor.matrixU().solveInPlace(m_permuted);
    for (Eigen::Index i = 0; i < n; ++i)
    {
        x[i] = m_permuted[permutation[i]];
    }
}
} // namespace masse
