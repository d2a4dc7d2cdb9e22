#pragma once
/// Eigen's symmetric permutations (a matrix's lower triangle, renumbered, written out in full or as one triangle) copy
/// each value to one or two places, and build a new matrix every time. A refresh of the same pattern needs only the
/// copies: where each value of the result comes from is found once, with the result's pattern (Eigen's, entry for
/// entry), and each refresh then gathers the values over ranges, without allocating (the same bits: copies only).

#include "core/Types.h"
#include "core/parallel/TaskPool.h"

#include <Eigen/SparseCore>

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>
#include <vector>

namespace masse
{
using PermutedSources = std::vector<Eigen::SparseMatrix<Real>::StorageIndex>;

namespace detail
{
/// Throws unless `a` is square and compressed (its value indices are then its entries'), naming `function`.
inline void requireSquareCompressed(const Eigen::SparseMatrix<Real>& a, const char* function)
{
    if (!a.isCompressed() || a.rows() != a.cols())
    {
        throw std::logic_error(std::string(function) + ": the matrix is not square and compressed");
    }
}

/// Calls visit(i, j, k) for each entry (i, j) of a's lower triangle, the diagonal included, k its value's index:
/// column by column, each column's rows in storage order.
template <class Visit> void forEachLowerEntry(const Eigen::SparseMatrix<Real>& a, const Visit& visit)
{
    const auto* outer = a.outerIndexPtr();
    const auto* inner = a.innerIndexPtr();
    for (std::size_t j = 0; j < std::size_t(a.cols()); ++j)
    {
        for (auto k = outer[j]; k < outer[j + 1]; ++k)
        {
            if (std::size_t(inner[k]) >= j)
            {
                visit(std::size_t(inner[k]), j, k);
            }
        }
    }
}
} // namespace detail

/// `permuted` = P A P^T in full (both triangles) from A's lower triangle, the diagonal included, where row and column i
/// of A become `newIndex[i]`, and for each of its values the index of a's value it copies. The pattern is Eigen's
/// `permuted = a.selfadjointView<Eigen::Lower>().twistedBy(P)`, each column's rows in increasing order, entry for
/// entry, so a factorisation reading it does its sums in the same order; Eigen builds it with its values through a
/// row-major copy, this the pattern alone in two counting passes: each value bucketed by its row, then the rows, in
/// increasing order, dealt out to their columns.
inline PermutedSources fullSymmetricPermutation(const Eigen::SparseMatrix<Real>& a,
                                                const Eigen::SparseMatrix<Real>::StorageIndex* newIndex,
                                                Eigen::SparseMatrix<Real>& permuted)
{
    using StorageIndex = Eigen::SparseMatrix<Real>::StorageIndex;
    detail::requireSquareCompressed(a, "fullSymmetricPermutation");
    const std::size_t n = std::size_t(a.cols());
    // Each lower value (i, j) is the entry (newIndex[i], newIndex[j]) and, off the diagonal, its mirror: a column of
    // the result has as many entries as the row of the same number.
    std::vector<StorageIndex> start(n + 1, 0);
    detail::forEachLowerEntry(a,
                              [&](std::size_t i, std::size_t j, StorageIndex)
                              {
                                  ++start[std::size_t(newIndex[j]) + 1];
                                  if (i != j)
                                  {
                                      ++start[std::size_t(newIndex[i]) + 1];
                                  }
                              });
    std::partial_sum(start.begin(), start.end(), start.begin());
    const std::size_t count = std::size_t(start[n]);
    std::vector<StorageIndex> rowColumn(count);
    PermutedSources rowSource(count);
    std::vector<StorageIndex> next(start.begin(), start.end() - 1);
    detail::forEachLowerEntry(a,
                              [&](std::size_t i, std::size_t j, StorageIndex k)
                              {
                                  const StorageIndex row = newIndex[i];
                                  const StorageIndex column = newIndex[j];
                                  StorageIndex at = next[std::size_t(row)]++;
                                  rowColumn[std::size_t(at)] = column;
                                  rowSource[std::size_t(at)] = k;
                                  if (i != j)
                                  {
                                      at = next[std::size_t(column)]++;
                                      rowColumn[std::size_t(at)] = row;
                                      rowSource[std::size_t(at)] = k;
                                  }
                              });
    permuted.resize(a.rows(), a.cols());
    permuted.resizeNonZeros(Eigen::Index(count));
    std::copy(start.begin(), start.end(), permuted.outerIndexPtr());
    PermutedSources sources(count);
    std::copy(start.begin(), start.end() - 1, next.begin());
    for (std::size_t row = 0; row < n; ++row)
    {
        for (StorageIndex e = start[row]; e < start[row + 1]; ++e)
        {
            const StorageIndex at = next[std::size_t(rowColumn[std::size_t(e)])]++;
            permuted.innerIndexPtr()[at] = StorageIndex(row);
            sources[std::size_t(at)] = rowSource[std::size_t(e)];
        }
    }
    return sources;
}

/// `upper` = A's upper triangle, the diagonal included, from its lower one, and for each of its values the index of
/// a's value it copies: Eigen's `upper.selfadjointView<Eigen::Upper>() = a.selfadjointView<Eigen::Lower>()`, each
/// column's rows in increasing order, entry for entry (a transposition by counting).
inline PermutedSources upperFromLower(const Eigen::SparseMatrix<Real>& a, Eigen::SparseMatrix<Real>& upper)
{
    using StorageIndex = Eigen::SparseMatrix<Real>::StorageIndex;
    detail::requireSquareCompressed(a, "upperFromLower");
    const std::size_t n = std::size_t(a.cols());
    std::vector<StorageIndex> start(n + 1, 0);
    detail::forEachLowerEntry(a, [&](std::size_t i, std::size_t, StorageIndex) { ++start[i + 1]; });
    std::partial_sum(start.begin(), start.end(), start.begin());
    const std::size_t count = std::size_t(start[n]);
    upper.resize(a.rows(), a.cols());
    upper.resizeNonZeros(Eigen::Index(count));
    std::copy(start.begin(), start.end(), upper.outerIndexPtr());
    PermutedSources sources(count);
    std::vector<StorageIndex> next(start.begin(), start.end() - 1);
    // Each column of the result gets its rows j in increasing order, the order the columns of a are walked in.
    detail::forEachLowerEntry(a,
                              [&](std::size_t i, std::size_t j, StorageIndex k)
                              {
                                  const StorageIndex at = next[i]++;
                                  upper.innerIndexPtr()[at] = StorageIndex(j);
                                  sources[std::size_t(at)] = k;
                              });
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
