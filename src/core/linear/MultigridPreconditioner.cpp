#include "core/linear/MultigridPreconditioner.h"

#include "core/parallel/ChunkedSum.h"
#include "core/parallel/TaskPool.h"

#include <algorithm>
#include <cmath>

namespace masse
{
namespace
{
/// Nodes per piece of a level's kernels: a constant, so the ranges do not depend on the thread count.
constexpr std::size_t nodeChunk = 1024;
/// Power iterations for each level's largest eigenvalue, and the margin put on the estimate (it is from below).
constexpr int levelPowerIterations = 12;
constexpr Real eigenvalueMargin = 1.1;

template <class Body> void overNodes(std::size_t nodes, const Body& body)
{
    parallelFor(nodes, nodeChunk, body);
}

/// Sorted, without repeats.
void sortUnique(std::vector<std::uint32_t>& v)
{
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
}

/// The pattern of (rows of `left`) x (rows of `right`): row i holds the union over left's row i of right's rows.
template <class RowsOf, class RightRows>
BlockSparseMatrix productPattern(std::size_t rows, const RowsOf& leftRow, const RightRows& rightRow)
{
    BlockSparseMatrix product;
    product.rowStart.assign(rows + 1, 0);
    std::vector<std::uint32_t> columns;
    for (std::size_t i = 0; i < rows; ++i)
    {
        columns.clear();
        leftRow(i, [&](std::uint32_t j) { rightRow(j, [&](std::uint32_t c) { columns.push_back(c); }); });
        sortUnique(columns);
        product.column.insert(product.column.end(), columns.begin(), columns.end());
        product.rowStart[i + 1] = std::uint32_t(product.column.size());
    }
    product.block.assign(product.column.size(), Mat3::Zero());
    return product;
}

/// A symmetric positive semi-definite block made definite: a coarse node whose members are all held along some
/// direction has no stiffness along it (its restricted residual is zero there too), and the smoother and the
/// coarsest factor need an inverse. A tiny fraction of its trace (the identity for an empty block) is added.
void makeDefinite(Mat3& block)
{
    const Real scale = block.trace() / Real(3);
    if (!(scale > 0))
    {
        block = Mat3::Identity();
        return;
    }
    block.diagonal().array() += Real(1e-10) * scale;
}
} // namespace

void MultigridPreconditioner::analyse(const SparseMatrix& a, const SpringSet& springs, std::size_t masses)
{
    m_levels.clear();
    m_ready = false;

    // Level 0: the pattern of the scalar matrix's 3x3 blocks. Column 3 i + r of the symmetric matrix is its row
    // 3 i + r, so block row i is read from columns 3 i, 3 i + 1, 3 i + 2.
    Level& fine = m_levels.emplace_back();
    const auto* outer = a.outerIndexPtr();
    const auto* inner = a.innerIndexPtr();
    fine.matrix.rowStart.assign(masses + 1, 0);
    m_fineSlots.clear();
    for (std::size_t i = 0; i < masses; ++i)
    {
        for (auto k = outer[3 * i]; k < outer[3 * i + 1]; k += 3)
        {
            const std::uint32_t column = std::uint32_t(inner[k] / 3);
            fine.matrix.column.push_back(column);
            std::array<SparseMatrix::StorageIndex, 3> slots{};
            for (std::size_t r = 0; r < 3; ++r)
            {
                const auto* begin = inner + outer[3 * i + r];
                const auto* end = inner + outer[3 * i + r + 1];
                slots[r] = SparseMatrix::StorageIndex(std::lower_bound(begin, end, inner[k]) - inner);
            }
            m_fineSlots.push_back(slots);
        }
        fine.matrix.rowStart[i + 1] = std::uint32_t(fine.matrix.column.size());
    }
    fine.matrix.block.assign(fine.matrix.column.size(), Mat3::Zero());
    m_fineFilter.assign(masses, Mat3::Identity());
    m_fineFiltered.assign(masses, 0);

    NodeGraph graph = planarGraph(springs, masses);
    while (graph.nodes() > coarsestNodes)
    {
        std::uint32_t count = 0;
        std::vector<std::uint32_t> aggregateOf = aggregate(graph, count);
        if (Real(count) > Real(0.8) * Real(graph.nodes()))
        {
            break; // the graph no longer coarsens (isolated masses): factor what is left
        }
        Level& level = m_levels.back();
        const BlockSparseMatrix& matrix = level.matrix;
        auto matrixRow = [&](std::size_t i, auto visit)
        {
            for (std::uint32_t k = matrix.rowStart[i]; k < matrix.rowStart[i + 1]; ++k)
            {
                visit(matrix.column[k]);
            }
        };
        // P = (I - w D^-1 A) P0: node i interpolates from the aggregates of its matrix neighbours (itself included).
        level.interpolation =
            productPattern(matrix.rows(), matrixRow, [&](std::uint32_t j, auto visit) { visit(aggregateOf[j]); });
        const BlockSparseMatrix& p = level.interpolation;
        // P^T by rows of the coarse level, each block remembering the P block it transposes.
        BlockSparseMatrix& restriction = level.restriction;
        restriction.rowStart.assign(std::size_t(count) + 1, 0);
        for (std::uint32_t c : p.column)
        {
            ++restriction.rowStart[c + 1];
        }
        for (std::size_t c = 0; c < count; ++c)
        {
            restriction.rowStart[c + 1] += restriction.rowStart[c];
        }
        restriction.column.resize(p.column.size());
        restriction.block.assign(p.column.size(), Mat3::Zero());
        level.transposeOf.resize(p.column.size());
        std::vector<std::uint32_t> next(restriction.rowStart.begin(), restriction.rowStart.end() - 1);
        for (std::size_t i = 0; i < p.rows(); ++i)
        {
            for (std::uint32_t k = p.rowStart[i]; k < p.rowStart[i + 1]; ++k)
            {
                const std::uint32_t slot = next[p.column[k]]++;
                restriction.column[slot] = std::uint32_t(i);
                level.transposeOf[slot] = k;
            }
        }
        level.product = productPattern(matrix.rows(), matrixRow,
                                       [&](std::uint32_t j, auto visit)
                                       {
                                           for (std::uint32_t k = p.rowStart[j]; k < p.rowStart[j + 1]; ++k)
                                           {
                                               visit(p.column[k]);
                                           }
                                       });
        const BlockSparseMatrix& product = level.product;
        BlockSparseMatrix coarse = productPattern(
            count,
            [&](std::size_t c, auto visit)
            {
                for (std::uint32_t k = restriction.rowStart[c]; k < restriction.rowStart[c + 1]; ++k)
                {
                    visit(restriction.column[k]);
                }
            },
            [&](std::uint32_t i, auto visit)
            {
                for (std::uint32_t k = product.rowStart[i]; k < product.rowStart[i + 1]; ++k)
                {
                    visit(product.column[k]);
                }
            });
        graph = contract(graph, aggregateOf, count);
        level.aggregateOf = std::move(aggregateOf);
        m_levels.emplace_back().matrix = std::move(coarse);
    }
    for (Level& level : m_levels)
    {
        const Eigen::Index size = Eigen::Index(3 * level.matrix.rows());
        level.inverseDiagonal.assign(level.matrix.rows(), Mat3::Identity());
        level.rhs.setZero(size);
        level.x.setZero(size);
        level.xNext.setZero(size);
        level.direction.setZero(size);
        level.residual.setZero(size);
    }
    m_coarsestPermuted.setZero(Eigen::Index(3 * m_levels.back().matrix.rows()));
}

void MultigridPreconditioner::setFilter(const std::vector<Index>& masses, const std::vector<Mat3>& filters)
{
    m_masses = &masses;
    m_filters = &filters;
}

void MultigridPreconditioner::copyFineMatrix(const SparseMatrix& a)
{
    Level& fine = m_levels.front();
    const Real* values = a.valuePtr();
    overNodes(fine.matrix.rows(),
              [&](std::size_t begin, std::size_t end)
              {
                  for (std::size_t i = begin; i < end; ++i)
                  {
                      bool coupled = false;
                      for (std::uint32_t k = fine.matrix.rowStart[i]; k < fine.matrix.rowStart[i + 1]; ++k)
                      {
                          Mat3& block = fine.matrix.block[k];
                          for (int r = 0; r < 3; ++r)
                          {
                              const Real* row = values + m_fineSlots[k][std::size_t(r)];
                              block(r, 0) = row[0];
                              block(r, 1) = row[1];
                              block(r, 2) = row[2];
                          }
                          coupled = coupled || (fine.matrix.column[k] != i && !block.isZero(0));
                      }
                      // A mass with no coupling left (pinned, or held in every direction) takes no coarse motion.
                      m_fineFilter[i] = coupled ? Mat3(Mat3::Identity()) : Mat3(Mat3::Zero());
                      m_fineFiltered[i] = coupled ? 0 : 1;
                  }
              });
    if (m_masses)
    {
        for (std::size_t k = 0; k < m_masses->size(); ++k)
        {
            const Index i = (*m_masses)[k];
            if (!m_fineFiltered[i])
            {
                m_fineFilter[i] = (*m_filters)[k];
                m_fineFiltered[i] = 1;
            }
        }
    }
}

void MultigridPreconditioner::invertDiagonal(std::size_t index)
{
    Level& level = m_levels[index];
    const BlockSparseMatrix& m = level.matrix;
    overNodes(m.rows(),
              [&](std::size_t begin, std::size_t end)
              {
                  for (std::size_t i = begin; i < end; ++i)
                  {
                      const Mat3& diagonal = m.block[m.find(i, std::uint32_t(i))];
                      level.inverseDiagonal[i] = diagonal.inverse();
                  }
              });
}

void MultigridPreconditioner::estimateLargestEigenvalue(std::size_t index)
{
    // Power iteration on D^-1 A from a fixed start with every frequency in it; the Rayleigh quotient
    // x.Ax / x.Dx of the last iterate bounds the largest eigenvalue from below.
    Level& level = m_levels[index];
    const std::size_t nodes = level.matrix.rows();
    Vector& x = level.x;
    Vector& ax = level.residual;
    for (Eigen::Index k = 0; k < x.size(); ++k)
    {
        const std::uint32_t hash = std::uint32_t(k) * 2654435761u;
        x[k] = Real(hash >> 8) / Real(1 << 24) - Real(0.5);
    }
    Real estimate = 1;
    for (int iteration = 0; iteration < levelPowerIterations; ++iteration)
    {
        overNodes(nodes,
                  [&](std::size_t begin, std::size_t end) { multiplyBlockRows(level.matrix, x, ax, begin, end); });
        const Real xAx = chunkedDot(x, ax);
        overNodes(nodes,
                  [&](std::size_t begin, std::size_t end)
                  {
                      for (std::size_t i = begin; i < end; ++i)
                      {
                          // x D x through D = (D^-1)^-1 would need the blocks again: keep D x in xNext.
                          level.xNext.segment<3>(Eigen::Index(3 * i)) =
                              level.matrix.block[level.matrix.find(i, std::uint32_t(i))] *
                              x.segment<3>(Eigen::Index(3 * i));
                      }
                  });
        const Real xDx = chunkedDot(x, level.xNext);
        if (xDx > 0)
        {
            estimate = xAx / xDx;
        }
        overNodes(nodes,
                  [&](std::size_t begin, std::size_t end)
                  {
                      for (std::size_t i = begin; i < end; ++i)
                      {
                          level.direction.segment<3>(Eigen::Index(3 * i)) =
                              level.inverseDiagonal[i] * ax.segment<3>(Eigen::Index(3 * i));
                      }
                  });
        const Real norm = std::sqrt(chunkedDot(level.direction, level.direction));
        if (!(norm > 0) || !std::isfinite(norm))
        {
            break;
        }
        x = level.direction / norm;
    }
    level.largestEigenvalue = eigenvalueMargin * std::max(estimate, Real(1e-12));
    x.setZero();
    level.direction.setZero();
}

void MultigridPreconditioner::smoothInterpolation(std::size_t index)
{
    // P = S (I - w D^-1 A) P0, w = 4 / (3 lambda_max(D^-1 A)): smoothed aggregation's prolongator (Vanek, Mandel and
    // Brezina 1996), with S the fine level's filter at this refresh (the identity on coarser levels).
    Level& level = m_levels[index];
    const bool fine = index == 0;
    const BlockSparseMatrix& a = level.matrix;
    BlockSparseMatrix& p = level.interpolation;
    const Real w = Real(4) / (Real(3) * level.largestEigenvalue / eigenvalueMargin);
    overNodes(a.rows(),
              [&](std::size_t begin, std::size_t end)
              {
                  for (std::size_t i = begin; i < end; ++i)
                  {
                      const std::uint32_t first = p.rowStart[i];
                      for (std::uint32_t k = first; k < p.rowStart[i + 1]; ++k)
                      {
                          p.block[k].setZero();
                      }
                      p.block[p.find(i, level.aggregateOf[i])] = Mat3::Identity();
                      const Mat3 scaled = -w * level.inverseDiagonal[i];
                      for (std::uint32_t k = a.rowStart[i]; k < a.rowStart[i + 1]; ++k)
                      {
                          p.block[p.find(i, level.aggregateOf[a.column[k]])] += scaled * a.block[k];
                      }
                      if (fine && m_fineFiltered[i])
                      {
                          for (std::uint32_t k = first; k < p.rowStart[i + 1]; ++k)
                          {
                              p.block[k] = (m_fineFilter[i] * p.block[k]).eval();
                          }
                      }
                  }
              });
    BlockSparseMatrix& r = level.restriction;
    overNodes(r.rows(),
              [&](std::size_t begin, std::size_t end)
              {
                  for (std::size_t c = begin; c < end; ++c)
                  {
                      for (std::uint32_t k = r.rowStart[c]; k < r.rowStart[c + 1]; ++k)
                      {
                          r.block[k] = p.block[level.transposeOf[k]].transpose();
                      }
                  }
              });
}

void MultigridPreconditioner::galerkin(std::size_t index)
{
    // A_c = P^T A P in two gathers: T = A P by fine rows, then P^T T by coarse rows.
    Level& level = m_levels[index];
    Level& next = m_levels[index + 1];
    const BlockSparseMatrix& a = level.matrix;
    const BlockSparseMatrix& p = level.interpolation;
    BlockSparseMatrix& t = level.product;
    overNodes(a.rows(),
              [&](std::size_t begin, std::size_t end)
              {
                  for (std::size_t i = begin; i < end; ++i)
                  {
                      const std::uint32_t first = t.rowStart[i];
                      for (std::uint32_t k = first; k < t.rowStart[i + 1]; ++k)
                      {
                          t.block[k].setZero();
                      }
                      for (std::uint32_t k = a.rowStart[i]; k < a.rowStart[i + 1]; ++k)
                      {
                          const std::uint32_t j = a.column[k];
                          std::uint32_t slot = first;
                          for (std::uint32_t q = p.rowStart[j]; q < p.rowStart[j + 1]; ++q)
                          {
                              while (t.column[slot] != p.column[q]) // both ascending: a merge, not a search
                              {
                                  ++slot;
                              }
                              t.block[slot] += a.block[k] * p.block[q];
                          }
                      }
                  }
              });
    const BlockSparseMatrix& r = level.restriction;
    BlockSparseMatrix& c = next.matrix;
    overNodes(c.rows(),
              [&](std::size_t begin, std::size_t end)
              {
                  for (std::size_t coarse = begin; coarse < end; ++coarse)
                  {
                      const std::uint32_t first = c.rowStart[coarse];
                      for (std::uint32_t k = first; k < c.rowStart[coarse + 1]; ++k)
                      {
                          c.block[k].setZero();
                      }
                      for (std::uint32_t q = r.rowStart[coarse]; q < r.rowStart[coarse + 1]; ++q)
                      {
                          const std::uint32_t i = r.column[q];
                          std::uint32_t slot = first;
                          for (std::uint32_t k = t.rowStart[i]; k < t.rowStart[i + 1]; ++k)
                          {
                              while (c.column[slot] != t.column[k])
                              {
                                  ++slot;
                              }
                              c.block[slot] += r.block[q] * t.block[k];
                          }
                      }
                      Mat3& diagonal = c.block[c.find(coarse, std::uint32_t(coarse))];
                      diagonal = Real(0.5) * (diagonal + diagonal.transpose()).eval();
                      makeDefinite(diagonal);
                  }
              });
}

bool MultigridPreconditioner::factorCoarsest()
{
    const BlockSparseMatrix& m = m_levels.back().matrix;
    std::vector<Eigen::Triplet<Real, SparseMatrix::StorageIndex>> triplets;
    triplets.reserve(9 * m.block.size());
    for (std::size_t i = 0; i < m.rows(); ++i)
    {
        for (std::uint32_t k = m.rowStart[i]; k < m.rowStart[i + 1]; ++k)
        {
            for (int r = 0; r < 3; ++r)
            {
                for (int col = 0; col < 3; ++col)
                {
                    triplets.emplace_back(SparseMatrix::StorageIndex(3 * i) + r,
                                          SparseMatrix::StorageIndex(3 * m.column[k]) + col, m.block[k](r, col));
                }
            }
        }
    }
    const Eigen::Index size = Eigen::Index(3 * m.rows());
    m_coarsestMatrix.resize(size, size);
    m_coarsestMatrix.setFromTriplets(triplets.begin(), triplets.end());
    m_coarsest.compute(m_coarsestMatrix);
    if (m_coarsest.info() != Eigen::Success)
    {
        return false;
    }
    m_coarsestDiagonal = m_coarsest.vectorD();
    return true;
}

bool MultigridPreconditioner::refresh(const SparseMatrix& a)
{
    ++m_refreshCount;
    copyFineMatrix(a);
    for (std::size_t level = 0; level + 1 < m_levels.size(); ++level)
    {
        invertDiagonal(level);
        estimateLargestEigenvalue(level);
        smoothInterpolation(level);
        galerkin(level);
    }
    m_ready = factorCoarsest();
    return m_ready;
}

void MultigridPreconditioner::apply(const Vector& r, Vector& z) const
{
    const Level& fine = m_levels.front();
    const bool filtered = m_masses && !m_masses->empty();
    fine.rhs = r;
    if (filtered)
    {
        for (std::size_t k = 0; k < m_masses->size(); ++k)
        {
            const Eigen::Index row = Eigen::Index(3 * (*m_masses)[k]);
            fine.rhs.segment<3>(row) = (*m_filters)[k] * r.segment<3>(row);
        }
    }
    cycle(0);
    z = fine.x;
    if (filtered)
    {
        for (std::size_t k = 0; k < m_masses->size(); ++k)
        {
            const Eigen::Index row = Eigen::Index(3 * (*m_masses)[k]);
            const Mat3& s = (*m_filters)[k];
            z.segment<3>(row) = s * z.segment<3>(row) + (r.segment<3>(row) - s * r.segment<3>(row));
        }
    }
}

void MultigridPreconditioner::cycle(std::size_t index) const
{
    if (index + 1 == m_levels.size())
    {
        solveCoarsest();
        return;
    }
    const Level& level = m_levels[index];
    const Level& next = m_levels[index + 1];
    const std::size_t nodes = level.matrix.rows();
    smooth(index, true);
    // The residual, restricted (P^T holds the fine level's filter).
    overNodes(nodes,
              [&](std::size_t begin, std::size_t end)
              {
                  multiplyBlockRows(level.matrix, level.x, level.residual, begin, end);
                  for (std::size_t i = begin; i < end; ++i)
                  {
                      const Eigen::Index row = Eigen::Index(3 * i);
                      level.residual.segment<3>(row) = level.rhs.segment<3>(row) - level.residual.segment<3>(row);
                  }
              });
    overNodes(next.matrix.rows(), [&](std::size_t begin, std::size_t end)
              { multiplyBlockRows(level.restriction, level.residual, next.rhs, begin, end); });
    cycle(index + 1);
    overNodes(nodes,
              [&](std::size_t begin, std::size_t end)
              {
                  multiplyBlockRows(level.interpolation, next.x, level.xNext, begin, end);
                  for (std::size_t i = 3 * begin; i < 3 * end; ++i)
                  {
                      level.x[Eigen::Index(i)] += level.xNext[Eigen::Index(i)];
                  }
              });
    smooth(index, false);
}

void MultigridPreconditioner::smooth(std::size_t index, bool fromZero) const
{
    // Chebyshev iteration on D^-1 A over [lambda_max / smoothedRange, lambda_max] (Saad, Iterative Methods, 12.3),
    // each step one sweep: w = rhs - A x, d = c1 d + c2 D^-1 w, x' = x + d, written to a second vector so that the
    // sweep reads only the old x.
    const Level& level = m_levels[index];
    const Real upper = level.largestEigenvalue;
    const Real lower = upper / smoothedRange;
    const Real theta = Real(0.5) * (upper + lower);
    const Real delta = Real(0.5) * (upper - lower);
    const Real sigma = theta / delta;
    Real rho = Real(1) / sigma;
    for (int step = 0; step < smoothingDegree; ++step)
    {
        Real keep = 0;
        Real scale = Real(1) / theta;
        if (step > 0)
        {
            const Real rhoNext = Real(1) / (Real(2) * sigma - rho);
            keep = rhoNext * rho;
            scale = Real(2) * rhoNext / delta;
            rho = rhoNext;
        }
        const bool zero = fromZero && step == 0;
        overNodes(level.matrix.rows(),
                  [&](std::size_t begin, std::size_t end)
                  {
                      if (!zero)
                      {
                          multiplyBlockRows(level.matrix, level.x, level.residual, begin, end);
                      }
                      for (std::size_t i = begin; i < end; ++i)
                      {
                          const Eigen::Index row = Eigen::Index(3 * i);
                          const Vec3 w = zero ? Vec3(level.rhs.segment<3>(row))
                                              : Vec3(level.rhs.segment<3>(row) - level.residual.segment<3>(row));
                          const Vec3 d =
                              keep * level.direction.segment<3>(row) + scale * (level.inverseDiagonal[i] * w);
                          level.direction.segment<3>(row) = d;
                          level.xNext.segment<3>(row) = zero ? d : Vec3(level.x.segment<3>(row) + d);
                      }
                  });
        level.x.swap(level.xNext);
    }
}

void MultigridPreconditioner::solveCoarsest() const
{
    // P^T L D L^T P x = b spelled out, as SimplicialLDLT::solve allocates on every call.
    const Level& level = m_levels.back();
    const auto& permutation = m_coarsest.permutationP().indices();
    const Eigen::Index n = level.rhs.size();
    for (Eigen::Index i = 0; i < n; ++i)
    {
        m_coarsestPermuted[permutation[i]] = level.rhs[i];
    }
    m_coarsest.matrixL().solveInPlace(m_coarsestPermuted);
    for (Eigen::Index i = 0; i < n; ++i)
    {
        m_coarsestPermuted[i] /= m_coarsestDiagonal[i];
    }
    m_coarsest.matrixU().solveInPlace(m_coarsestPermuted);
    for (Eigen::Index i = 0; i < n; ++i)
    {
        level.x[i] = m_coarsestPermuted[permutation[i]];
    }
}
} // namespace masse
