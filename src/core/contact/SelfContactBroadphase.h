#pragma once
/// The broadphase of the sheet's self-contact: which (vertex, triangle) pairs of the sheet's surface may come within
/// the contact radius during a frame. The Bullet bridge implements it with a btDbvt over the triangles; the core sees
/// only this interface, asks it at each frame's start (and again when a mass outruns its skin, SelfContact.h) and
/// tests the pairs it returns after every substep.

#include "core/Types.h"
#include "core/lattice/LatticeSurface.h"

#include <algorithm>
#include <vector>

namespace masse
{
/// What findSweptPairs's test in the vertex's frame of motion allows beyond the reaches, in radii: how far the
/// responses after the solve and the obstacle contact may still move a mass off its line (a push of up to about a
/// radius). With this allowance the test lists every pair the boxes alone list: the 128x2x128 fold over the rod gives
/// the same bits either way.
constexpr Real sweptFrameAllowance = 1;

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

/// The distance from point x to the box low..high, less the radius: how far x is from touching anything the box
/// holds. Never more than from a smaller box inside it (each step rounds monotonically), so a box over many
/// triangles bounds the gap of each from below.
inline Real gapToBox(const Vec3& x, const Vec3& low, const Vec3& high, Real radius)
{
    const Vec3 outside = (low - x).cwiseMax(x - high);
    return outside.cwiseMax(Vec3::Zero()).norm() - radius;
}

/// Which pairs the arrivals of a frame's one solve (SelfContact::weighArrival) may take: a pair is turned away when
/// its vertex is farther from touching the triangle's box (gapToBox, the triangle's masses at the step's start) than
/// both `rest` and the step's length times the fastest of the triangle's masses relative to the vertex, each with
/// `slack` to spare. Most pairs of the swept boxes are turned away: a tilted sheet's neighbours moving together. The
/// weighing and the broadphase's list for it share this one test, so the list holds every pair the weighing takes.
struct ArrivalTest
{
    const std::vector<Vec3>* velocity = nullptr; ///< per mass, m/s
    Real dt = 0;                                 ///< s, the step
    Real rest = 0;                               ///< m, how near touching a resting pair counts as arriving
    Real slack = 0;                              ///< m, so that rounding decides no pair the closest point would weigh

    /// `gap` as gapToBox gives it, `relativeSpeed` the fastest of the triangle's masses relative to the vertex. Also
    /// true of a group of triangles whose gap is bounded from below and speed from above by those given.
    bool mayArrive(Real gap, Real relativeSpeed) const
    {
        return !(gap > rest + slack) || !(gap > dt * relativeSpeed + slack);
    }
    /// The fastest of triangle t's masses relative to vertex i.
    Real relativeSpeed(Index i, const Triangle& t) const
    {
        const std::vector<Vec3>& v = *velocity;
        return std::max({(v[t[0]] - v[i]).norm(), (v[t[1]] - v[i]).norm(), (v[t[2]] - v[i]).norm()});
    }
};

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
    /// Replaces `out` by every pair of a vertex of `vertices` and a triangle whose boxes over a motion overlap (the
    /// vertex's box holds it at `from` and at `to`, grown by reach[v]; the triangle's holds its masses at both, grown
    /// by `radius` plus their largest reach) and which, in the vertex's own frame, may meet: at `to`, along every
    /// axis, the vertex lies within the radius, reach[v], the triangle's masses' largest reach, the most their moves
    /// differ from its own (along that axis) and sweptFrameAllowance radii of the triangle's box. So a pair whose
    /// masses each keep within their reach of the straight line from `from` to `to`, and that comes within the radius
    /// at some moment, is listed; two masses moving side by side or one behind the other are not, however fast. Pairs
    /// in the order and with the exclusions of findPairs.
    virtual void findSweptPairs(const std::vector<Vec3>& from, const std::vector<Vec3>& to,
                                const std::vector<Real>& reach, Real radius, const std::vector<Index>& vertices,
                                const SelfContactExclusions& excluded, std::vector<SelfContactPair>& out) = 0;
    /// The pairs findSweptPairs would list that `arrival` also takes (ArrivalTest::mayArrive, the triangle's box at
    /// `from` and the velocities it names), in the same order: the list of a frame's start, which feeds only the
    /// arrivals. An implementation may skip whole groups of triangles by bounds on their gap and relative speed.
    virtual void findSweptArrivingPairs(const std::vector<Vec3>& from, const std::vector<Vec3>& to,
                                        const std::vector<Real>& reach, Real radius, const std::vector<Index>& vertices,
                                        const SelfContactExclusions& excluded, const ArrivalTest& arrival,
                                        std::vector<SelfContactPair>& out) = 0;
};
} // namespace masse
