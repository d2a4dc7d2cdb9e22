#include "core/linear/SlotMatrix.h"

#include "core/InputError.h"

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
    const Eigen::Index size = Eigen::Index(B * masses);
    std::vector<Eigen::Triplet<Real, StorageIndex>> triplets;
    triplets.reserve(std::size_t(B * B) * (masses + 2 * ends.size()));
    auto addBlock = [&](std::size_t row, std::size_t column)
    {
        for (int c = 0; c < B; ++c)
        {
            for (int r = 0; r < B; ++r)
            {
                triplets.emplace_back(StorageIndex(B * row) + r, StorageIndex(B * column) + c, Real(0));
            }
        }
    };
    for (std::size_t i = 0; i < masses; ++i)
    {
        addBlock(i, i);
    }
    for (const SpringEnds& e : ends)
    {
        addBlock(e.a, e.b);
        addBlock(e.b, e.a);
    }
    m_matrix.resize(size, size);
    m_matrix.setFromTriplets(triplets.begin(), triplets.end());
    m_matrix.makeCompressed();

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
