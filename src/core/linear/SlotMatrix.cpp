#include "core/linear/SlotMatrix.h"

#include "core/InputError.h"
#include "core/lattice/SpringAdjacency.h"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

namespace masse
{
template <int B> void SlotMatrix<B>::build(std::size_t masses, const std::vector<SpringEnds>& ends)
{
    if (masses > maxMasses())
    {
        throw InputError("the sheet's " + std::to_string(masses) + " masses are too many for a sparse matrix of " +
                         std::to_string(B) + "x" + std::to_string(B) + " blocks (at most " +
                         std::to_string(maxMasses()) + ")");
    }
    // Each mass's block column holds its own block and one per mass a spring joins it to, in increasing mass order:
    // the pattern setFromTriplets makes from every block, written straight into the compressed arrays from the
    // springs' adjacency, without sorting nine triplets a block (some three million for a 128x2x128 sheet).
    const SpringAdjacency adjacency = buildSpringAdjacency(ends, masses); // refuses a spring to a missing mass
    std::vector<std::size_t> first(masses + 1, 0); // mass j's distinct joined masses: joined[first[j], first[j + 1])
    std::vector<Index> joined;
    joined.reserve(masses + adjacency.entries.size());
    for (std::size_t j = 0; j < masses; ++j)
    {
        const auto begin = std::ptrdiff_t(joined.size());
        joined.push_back(Index(j));
        for (std::size_t e = adjacency.offsets[j]; e < adjacency.offsets[j + 1]; ++e)
        {
            joined.push_back(adjacency.entries[e].other);
        }
        std::sort(joined.begin() + begin, joined.end());
        joined.erase(std::unique(joined.begin() + begin, joined.end()), joined.end());
        first[j + 1] = joined.size();
    }
    const std::size_t blocks = joined.size();
    if (std::size_t(B * B) * blocks > std::size_t(std::numeric_limits<StorageIndex>::max()))
    {
        throw InputError("the sheet's " + std::to_string(ends.size()) +
                         " springs are too many for a sparse matrix of " + std::to_string(B) + "x" + std::to_string(B) +
                         " blocks");
    }
    const Eigen::Index size = Eigen::Index(B * masses);
    m_matrix = SparseMatrix(size, size);
    const std::size_t entries = std::size_t(B * B) * blocks;
    m_matrix.resizeNonZeros(Eigen::Index(entries));
    StorageIndex* outer = m_matrix.outerIndexPtr();
    StorageIndex* inner = m_matrix.innerIndexPtr();
    std::fill(m_matrix.valuePtr(), m_matrix.valuePtr() + entries, Real(0));
    StorageIndex entry = 0;
    for (std::size_t j = 0; j < masses; ++j)
    {
        for (int c = 0; c < B; ++c)
        {
            outer[B * j + std::size_t(c)] = entry;
            for (std::size_t k = first[j]; k < first[j + 1]; ++k)
            {
                for (int r = 0; r < B; ++r)
                {
                    inner[entry++] = StorageIndex(B * joined[k] + r);
                }
            }
        }
    }
    outer[size] = entry;

    m_diagonal.resize(masses);
    for (std::size_t i = 0; i < masses; ++i)
    {
        m_diagonal[i] = slotsOf(i, i);
    }
    m_ab.resize(ends.size());
    m_ba.resize(ends.size());
    for (std::size_t s = 0; s < ends.size(); ++s)
    {
        m_ab[s] = slotsOf(ends[s].a, ends[s].b);
        m_ba[s] = slotsOf(ends[s].b, ends[s].a);
    }
}

template <int B> typename SlotMatrix<B>::Slots SlotMatrix<B>::slotsOf(std::size_t row, std::size_t column) const
{
    const std::size_t masses = std::size_t(m_matrix.cols() / B);
    if (row >= masses || column >= masses)
    {
        throw std::out_of_range("SlotMatrix: block (" + std::to_string(row) + ", " + std::to_string(column) +
                                ") of a matrix over " + std::to_string(masses) + " masses");
    }
    Slots slots{};
    const StorageIndex* outer = m_matrix.outerIndexPtr();
    const StorageIndex* inner = m_matrix.innerIndexPtr();
    for (int c = 0; c < B; ++c)
    {
        const std::size_t col = std::size_t(B) * column + std::size_t(c);
        const StorageIndex* begin = inner + outer[col];
        const StorageIndex* end = inner + outer[col + 1];
        const StorageIndex* found = std::lower_bound(begin, end, StorageIndex(B * row));
        if (found == end || *found != StorageIndex(B * row))
        {
            throw std::out_of_range("SlotMatrix: block (" + std::to_string(row) + ", " + std::to_string(column) +
                                    ") is not in the pattern: no spring joins the two masses");
        }
        slots[std::size_t(c)] = StorageIndex(found - inner);
    }
    return slots;
}

template class SlotMatrix<1>;
template class SlotMatrix<3>;
} // namespace masse
