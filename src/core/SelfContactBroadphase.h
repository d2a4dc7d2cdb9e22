#pragma once
/// The broadphase of the sheet's self-contact: which (vertex, triangle) pairs of the sheet's surface may come within
/// the contact radius during a frame. The Bullet bridge implements it with a btDbvt over the triangles; the core sees
/// only this interface, asks it at each frame's start (and again when a mass outruns its skin, SelfContact.h) and
/// tests the pairs it returns after every substep.

#include "LatticeSurface.h"
#include "Types.h"

#include <vector>

namespace masse
{
/// A surface vertex and a surface triangle that may touch.
struct SelfContactPair
{
    Index vertex = 0;
    Index triangle = 0; ///< into the triangles given to setTriangles
};

class SelfContactBroadphase
{
public:
    virtual ~SelfContactBroadphase() = default;
    /// The surface, once (its topology never changes).
    virtual void setTriangles(const std::vector<Triangle>& triangles) = 0;
    /// Replaces `out` by every pair of a vertex of `vertices` and a triangle whose boxes overlap: the vertex's box
    /// is x[v] grown by reach[v]; a triangle's is its vertices' box grown by their largest reach plus `radius`.
    /// Pairs are listed by vertex in the order of `vertices`, each vertex's triangles in an order that depends only on
    /// the calls made so far, so the list is the same whatever the thread count.
    virtual void findPairs(const std::vector<Vec3>& x, const std::vector<Real>& reach, Real radius,
                           const std::vector<Index>& vertices, std::vector<SelfContactPair>& out) = 0;
};
} // namespace masse
