#pragma once
/// Eigen's symmetric permutations (a matrix's lower triangle, renumbered, written out in full or as one triangle) copy
/// each value to one or two places, and build a new matrix every time. A refresh of the same pattern needs only the
/// copies: where each value of the result comes from is found once, by permuting a matrix whose values are their own
/// indices, and each refresh then gathers the values over ranges, without allocating (the same bits: copies only).

#include "core/Types.h"
#include "core/parallel/TaskPool.h"

#include <Eigen/SparseCore>

#include <stdexcept>
#include <vector>

namespace masse
{
using PermutedSources = std::vector<Eigen::SparseMatrix<Real>::StorageIndex>;

/// `permuted` = permute(a), and for each of its values the index of a's value it copies. `a` is compressed, with
/// fewer values than double counts exactly.
template <class Permute>
PermutedSources findPermutedSources(const Eigen::SparseMatrix<Real>& a, const Permute& permute,
                                    Eigen::SparseMatrix<Real>& permuted)
{
    if (!a.isCompressed())
    {
        throw std::logic_error("findPermutedSources: the matrix is not compressed");
    }
    Eigen::SparseMatrix<Real> indices = a;
    for (Eigen::Index k = 0; k < indices.nonZeros(); ++k)
    {
        indices.valuePtr()[k] = Real(k);
    }
    permuted = permute(indices);
    permuted.makeCompressed();
    PermutedSources sources(std::size_t(permuted.nonZeros()));
    for (std::size_t k = 0; k < sources.size(); ++k)
    {
        sources[k] = Eigen::SparseMatrix<Real>::StorageIndex(permuted.valuePtr()[k]);
    }
    return sources;
}

/// The values of `permuted` from those of `a` (the pattern findPermutedSources saw).
inline void gatherPermutedValues(const Eigen::SparseMatrix<Real>& a, const PermutedSources& sources,
                                 Eigen::SparseMatrix<Real>& permuted)
{
    const Real* from = a.valuePtr();
    Real* to = permuted.valuePtr();
    parallelFor(sources.size(), 65536,
                [&](std::size_t begin, std::size_t end)
                {
                    for (std::size_t k = begin; k < end; ++k)
                    {
                        to[k] = from[sources[k]];
                    }
                });
}
} // namespace masse
