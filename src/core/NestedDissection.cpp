#include "NestedDissection.h"

#include <algorithm>

namespace masse
{
namespace
{
/// Parts at most this large are eliminated in index order: below it the separators no longer pay.
constexpr std::size_t leafSize = 32;

struct Dissection
{
    const std::vector<Vec3>& positions;
    std::vector<std::size_t> neighbourStart; ///< CSR adjacency of the springs
    std::vector<Index> neighbours;
    std::vector<int> side; ///< scratch: 1 for masses of the current right half
    std::vector<Index> order;

    void dissect(std::vector<Index> part)
    {
        if (part.size() <= leafSize)
        {
            std::sort(part.begin(), part.end());
            order.insert(order.end(), part.begin(), part.end());
            return;
        }
        Vec3 low = positions[part[0]];
        Vec3 high = low;
        for (Index i : part)
        {
            low = low.cwiseMin(positions[i]);
            high = high.cwiseMax(positions[i]);
        }
        int axis = 0;
        (high - low).maxCoeff(&axis);
        const std::size_t half = part.size() / 2;
        std::nth_element(part.begin(), part.begin() + std::ptrdiff_t(half), part.end(),
                         [&](Index a, Index b)
                         {
                             const Real pa = positions[a][axis];
                             const Real pb = positions[b][axis];
                             return pa < pb || (pa == pb && a < b);
                         });
        std::vector<Index> left(part.begin(), part.begin() + std::ptrdiff_t(half));
        std::vector<Index> right(part.begin() + std::ptrdiff_t(half), part.end());
        for (Index i : right)
        {
            side[i] = 1;
        }
        std::vector<Index> separator;
        std::vector<Index> rest;
        for (Index i : left)
        {
            bool touchesRight = false;
            for (std::size_t k = neighbourStart[i]; k < neighbourStart[i + 1] && !touchesRight; ++k)
            {
                touchesRight = side[neighbours[k]] == 1;
            }
            (touchesRight ? separator : rest).push_back(i);
        }
        for (Index i : right)
        {
            side[i] = 0;
        }
        if (rest.empty()) // no progress (a part that is all separator): give up on dissecting it
        {
            std::sort(part.begin(), part.end());
            order.insert(order.end(), part.begin(), part.end());
            return;
        }
        dissect(std::move(rest));
        dissect(std::move(right));
        std::sort(separator.begin(), separator.end());
        order.insert(order.end(), separator.begin(), separator.end());
    }
};
} // namespace

std::vector<Index> nestedDissectionOrder(const std::vector<Vec3>& positions, const SpringSet& springs)
{
    const std::size_t n = positions.size();
    Dissection d{positions, std::vector<std::size_t>(n + 1, 0), {}, std::vector<int>(n, 0), {}};
    for (const SpringEnds& e : springs.ends)
    {
        ++d.neighbourStart[e.a + 1];
        ++d.neighbourStart[e.b + 1];
    }
    for (std::size_t i = 0; i < n; ++i)
    {
        d.neighbourStart[i + 1] += d.neighbourStart[i];
    }
    d.neighbours.resize(d.neighbourStart[n]);
    std::vector<std::size_t> fill(d.neighbourStart.begin(), d.neighbourStart.end() - 1);
    for (const SpringEnds& e : springs.ends)
    {
        d.neighbours[fill[e.a]++] = e.b;
        d.neighbours[fill[e.b]++] = e.a;
    }
    std::vector<Index> all(n);
    for (std::size_t i = 0; i < n; ++i)
    {
        all[i] = Index(i);
    }
    d.order.reserve(n);
    d.dissect(std::move(all));
    return d.order;
}
} // namespace masse
