#pragma once
/// The broadphase of the sheet's self-contact: which (vertex, triangle) pairs of the sheet's surface may come within
/// the contact radius during a frame. The Bullet bridge implements it with a btDbvt over the triangles; the core sees
/// only this interface, asks it at each frame's start (and again when a mass outruns its skin, SelfContact.h) and
/// tests the pairs it returns after every substep.

#include "LatticeSurface.h"
#include "Types.h"

#include <algorithm>
#include <vector>

namespace masse
{
/// A surface vertex and a surface triangle that may touch.
struct SelfContactPair
{
    Index vertex = 0;
    Index triangle = 0; ///< into the triangles given to setTriangles
};

/// The triangles each mass is never paired with (SelfContact.h says which): a table over every mass, built once.
struct SelfContactExclusions
{
    std::vector<std::size_t> start; ///< mass i's are triangles[start[i], start[i + 1])
    std::vector<Index> triangles;   ///< increasing within each mass

    bool excludes(Index vertex, Index triangle) const
    {
        const auto first = triangles.begin() + std::ptrdiff_t(start[vertex]);
        const auto last = triangles.begin() + std::ptrdiff_t(start[vertex + 1]);
        return std::binary_search(first, last, triangle);
    }
};

/// Whether vertex i may come within `radius` of triangle t in a step of dt, all four masses moving on at their
/// velocities v, or lies within `rest` of that now. In the vertex's frame each of the triangle's masses moves by its
/// velocity relative to the vertex's times dt, so the triangle stays inside its box (low..high, its masses' box at x)
/// stretched along each axis by the least and the most of those moves; the test is the vertex's distance from that
/// box against the radius plus `rest`, with a millionth of the radius to spare for rounding. Two masses moving
/// together pass it only where they are close, however fast they move. The self-contact's arrivals and the
/// broadphase's list of them share this one test, so the list holds exactly the pairs the arrivals weigh.
inline bool mayArrive(const std::vector<Vec3>& x, const std::vector<Vec3>& v, Index i, const Triangle& t,
                      const Vec3& low, const Vec3& high, Real dt, Real radius, Real rest)
{
    const Vec3 move0 = (v[t[0]] - v[i]) * dt;
    const Vec3 move1 = (v[t[1]] - v[i]) * dt;
    const Vec3 move2 = (v[t[2]] - v[i]) * dt;
    const Vec3 sweptLow = low + move0.cwiseMin(move1).cwiseMin(move2).cwiseMin(Vec3::Zero());
    const Vec3 sweptHigh = high + move0.cwiseMax(move1).cwiseMax(move2).cwiseMax(Vec3::Zero());
    const Vec3 outside = (sweptLow - x[i]).cwiseMax(x[i] - sweptHigh).cwiseMax(Vec3::Zero());
    const Real reach = radius + rest + Real(1e-6) * radius;
    return !(outside.squaredNorm() > reach * reach);
}

class SelfContactBroadphase
{
public:
    virtual ~SelfContactBroadphase() = default;
    /// The surface, once (its topology never changes).
    virtual void setTriangles(const std::vector<Triangle>& triangles) = 0;
    /// Replaces `out` by every pair of a vertex of `vertices` and a triangle closer than `radius` plus reach[v] plus
    /// the largest reach of the triangle's masses, except the pairs `excluded` names (an implementation finds them
    /// by boxes: the vertex's is x[v] grown by reach[v], a triangle's is its vertices' box grown by their largest
    /// reach plus `radius`; then measures the distance). Pairs are listed by vertex in the order of `vertices`, each
    /// vertex's triangles in an order that depends only on the calls made so far, so the list is the same whatever the
    /// thread count. The exclusions are tested where the pairs are found (on every thread), so the excluded ones, most
    /// of a flat sheet's neighbourhood, are never stored.
    virtual void findPairs(const std::vector<Vec3>& x, const std::vector<Real>& reach, Real radius,
                           const std::vector<Index>& vertices, const SelfContactExclusions& excluded,
                           std::vector<SelfContactPair>& out) = 0;
    /// Replaces `out` by every pair of a vertex of `vertices` and a triangle whose boxes over a motion overlap: the
    /// vertex's box holds it at `from` and at `to`, grown by reach[v]; the triangle's holds its masses at both, grown
    /// by `radius` plus their largest reach. So a pair whose masses each keep within their reach of the straight line
    /// from `from` to `to`, and that comes within the radius at some moment, is listed; two masses moving side by
    /// side are not, however fast. Pairs in the order and with the exclusions of findPairs.
    virtual void findSweptPairs(const std::vector<Vec3>& from, const std::vector<Vec3>& to,
                                const std::vector<Real>& reach, Real radius, const std::vector<Index>& vertices,
                                const SelfContactExclusions& excluded, std::vector<SelfContactPair>& out) = 0;
    /// Replaces `out` by every pair of a vertex of `vertices` and a triangle that passes mayArrive at positions x,
    /// velocities v and step dt: the pairs a step of one solve may carry within the radius at the present velocities,
    /// or that rest within `rest` of it. Pairs in the order and with the exclusions of findPairs.
    virtual void findArrivingPairs(const std::vector<Vec3>& x, const std::vector<Vec3>& v, Real dt, Real radius,
                                   Real rest, const std::vector<Index>& vertices, const SelfContactExclusions& excluded,
                                   std::vector<SelfContactPair>& out) = 0;
};
} // namespace masse
