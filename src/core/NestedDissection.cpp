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
    int parallelDepth;
    DissectionOrder result;

    /// Appends `part`, in index order, as one range; a part at or above the parallel depth is a stage-0 range.
    void appendWhole(std::vector<Index>& part, int depth)
    {
        std::sort(part.begin(), part.end());
        const std::size_t begin = result.order.size();
        result.order.insert(result.order.end(), part.begin(), part.end());
        if (depth <= parallelDepth)
        {
            result.stages[0].push_back({begin, result.order.size()});
        }
    }

    void dissect(std::vector<Index> part, int depth)
    {
        if (part.size() <= leafSize)
        {
            appendWhole(part, depth);
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
            appendWhole(part, depth);
            return;
        }
        const std::size_t begin = result.order.size();
        dissect(std::move(rest), depth + 1);
        dissect(std::move(right), depth + 1);
        std::sort(separator.begin(), separator.end());
        const std::size_t separatorBegin = result.order.size();
        result.order.insert(result.order.end(), separator.begin(), separator.end());
        if (depth == parallelDepth) // the whole part is one range: its own elimination is sequential
        {
            result.stages[0].push_back({begin, result.order.size()});
        }
        else if (depth < parallelDepth)
        {
            result.stages[std::size_t(parallelDepth - depth)].push_back({separatorBegin, result.order.size()});
        }
    }
};
} // namespace

DissectionOrder nestedDissection(const std::vector<Vec3>& positions, const SpringSet& springs, int parallelDepth)
{
    const std::size_t n = positions.size();
    Dissection d{positions, std::vector<std::size_t>(n + 1, 0), {}, std::vector<int>(n, 0), parallelDepth, {}};
    d.result.stages.resize(std::size_t(std::max(parallelDepth, 0)) + 1);
    for (const SpringEnds& e : springs.ends())
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
    for (const SpringEnds& e : springs.ends())
    {
        d.neighbours[fill[e.a]++] = e.b;
        d.neighbours[fill[e.b]++] = e.a;
    }
    std::vector<Index> all(n);
    for (std::size_t i = 0; i < n; ++i)
    {
        all[i] = Index(i);
    }
    d.result.order.reserve(n);
    d.dissect(std::move(all), 0);
    return d.result;
}
} // namespace masse
