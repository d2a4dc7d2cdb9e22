#include "core/contact/Webbing.h"

#include <algorithm>
#include <numeric>

namespace masse
{
namespace
{
/// Disjoint sets of masses, joined by union by index (the smaller root wins, so the result never depends on the
/// order of the joins).
class MassSets
{
public:
    explicit MassSets(std::size_t count) : m_parent(count) { std::iota(m_parent.begin(), m_parent.end(), Index(0)); }
    Index root(Index i)
    {
        while (m_parent[i] != i)
        {
            m_parent[i] = m_parent[m_parent[i]];
            i = m_parent[i];
        }
        return i;
    }
    void join(Index a, Index b)
    {
        const Index ra = root(a);
        const Index rb = root(b);
        if (ra != rb)
        {
            m_parent[std::max(ra, rb)] = std::min(ra, rb);
        }
    }

private:
    std::vector<Index> m_parent;
};
} // namespace

std::vector<WebbingPlace> findWebbing(SelfContact& surface, const Lattice& lattice, const std::vector<Vec3>& x,
                                      Real distance)
{
    std::vector<SelfContactPair> pairs;
    surface.pairsWithin(x, distance, pairs);
    const std::size_t n = x.size();
    std::vector<std::uint8_t> onSheet(n, 0);
    MassSets sets(n);
    for (const SelfContactPair& pair : pairs)
    {
        const Triangle& t = surface.triangles()[pair.triangle];
        onSheet[pair.vertex] = 1;
        for (const Index i : t)
        {
            onSheet[i] = 1;
            sets.join(pair.vertex, i);
        }
    }
    for (const SpringEnds& spring : lattice.springs.ends())
    {
        if (onSheet[spring.a] && onSheet[spring.b])
        {
            sets.join(spring.a, spring.b);
        }
    }
    std::vector<std::vector<Index>> byRoot(n);
    for (Index i = 0; i < Index(n); ++i)
    {
        if (onSheet[i])
        {
            byRoot[sets.root(i)].push_back(i);
        }
    }
    std::vector<WebbingPlace> places;
    for (std::vector<Index>& masses : byRoot)
    {
        if (masses.empty())
        {
            continue;
        }
        WebbingPlace place;
        place.masses = std::move(masses);
        place.low = place.high = x[place.masses.front()];
        place.restLow = place.restHigh = lattice.position[place.masses.front()];
        for (const Index i : place.masses)
        {
            place.centre += x[i];
            place.low = place.low.cwiseMin(x[i]);
            place.high = place.high.cwiseMax(x[i]);
            place.restLow = place.restLow.cwiseMin(lattice.position[i]);
            place.restHigh = place.restHigh.cwiseMax(lattice.position[i]);
        }
        place.centre /= Real(place.masses.size());
        places.push_back(std::move(place));
    }
    // Built in order of their lowest mass; a stable sort by size keeps that order among equals.
    std::stable_sort(places.begin(), places.end(),
                     [](const WebbingPlace& a, const WebbingPlace& b) { return a.masses.size() > b.masses.size(); });
    return places;
}
} // namespace masse
