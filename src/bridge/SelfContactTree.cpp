#include "SelfContactTree.h"

#include "BulletMath.h"

#include "core/contact/ClosestPointOnTriangle.h"
#include "core/parallel/TaskPool.h"

#include <BulletCollision/BroadphaseCollision/btDbvt.h>

#include <algorithm>
#include <array>
#include <cstdint>

namespace masse::bridge
{
namespace
{
/// Surface vertices per range of the queries: the pairs gather where the sheet folds, and small ranges let the
/// threads share that part evenly.
constexpr std::size_t selfQueryChunkSize = 512;

/// Vertices whose boxes are merged into one walk of the tree: consecutive surface vertices are neighbours along a
/// lattice row, so the group's box is little larger than one vertex's, and the tree is walked once for the group
/// instead of once per vertex. Each vertex then scans the group's leaves.
constexpr std::size_t selfQueryGroupSize = 4;

/// Marks the triangles one vertex is never paired with, so each leaf the vertex meets is tested by one load instead
/// of a binary search of its list (a query meets a few hundred leaves, most of them its excluded neighbourhood). A
/// mark is the number of the vertex's turn, so nothing is cleared between vertices. One per thread, kept between
/// lists: the queries' ranges run on any thread, and what a range finds does not depend on which.
struct ExclusionMarks
{
    std::vector<std::uint32_t> turnOf; ///< per triangle, the turn that last marked it
    std::uint32_t turn = 0;

    void mark(const SelfContactExclusions& excluded, Index vertex, std::size_t triangleCount)
    {
        if (turnOf.size() != triangleCount || ++turn == 0)
        {
            turnOf.assign(triangleCount, 0);
            turn = 1;
        }
        for (std::size_t k = excluded.start[vertex]; k < excluded.start[vertex + 1]; ++k)
        {
            turnOf[excluded.triangles[k]] = turn;
        }
    }
    bool marked(Index triangle) const { return turnOf[triangle] == turn; }
};

btDbvtVolume selfContactBox(const Vec3& low, const Vec3& high, Real margin)
{
    const Vec3 grow = Vec3::Constant(margin);
    return btDbvtVolume::FromMM(toBullet(low - grow), toBullet(high + grow));
}

/// Vertex v's box over its motion from `from` to `to`, grown by its reach.
btDbvtVolume sweptBox(const std::vector<Vec3>& from, const std::vector<Vec3>& to, const std::vector<Real>& reach,
                      Index v)
{
    return selfContactBox(from[v].cwiseMin(to[v]), from[v].cwiseMax(to[v]), reach[v]);
}

/// For the lists that walk every node a group's box overlaps: no other bound.
constexpr auto everyNode = [](const Index* /*group*/, std::size_t /*count*/)
{ return [](std::uint32_t /*node*/) { return true; }; };

/// btDbvt's own overlap test (Intersect), on a flattened node's box.
bool overlaps(const SelfContactTree::FlatNode& node, const btDbvtVolume& box)
{
    const btVector3& low = box.Mins();
    const btVector3& high = box.Maxs();
    return node.low[0] <= high.x() && node.high[0] >= low.x() && node.low[1] <= high.y() && node.high[1] >= low.y() &&
           node.low[2] <= high.z() && node.high[2] >= low.z();
}
} // namespace

SelfContactTree::SelfContactTree() : m_tree(std::make_unique<btDbvt>()) {}

SelfContactTree::~SelfContactTree() = default;

void SelfContactTree::setTriangles(const std::vector<Triangle>& triangles)
{
    m_tree->clear();
    m_flatIsCurrent = false;
    m_triangles = triangles;
    m_leaves.assign(triangles.size(), nullptr);
    m_low.assign(triangles.size(), Vec3::Zero());
    m_high.assign(triangles.size(), Vec3::Zero());
}

void SelfContactTree::refit(const std::vector<Vec3>& from, const std::vector<Vec3>& to, const std::vector<Real>& reach,
                            Real radius)
{
    // A leaf's box is the triangle's box (over `from` and `to` for a swept list) grown by the farthest its masses
    // may move beyond that plus the radius. A leaf
    // whose stored box still holds that stays as it is; one that does not (or has grown past twice the box it needs,
    // after the sheet slowed down) is reinserted with a fat box, grown by another quarter radius, so a sheet in slow
    // motion rebuilds little of the tree from list to list.
    for (std::size_t k = 0; k < m_triangles.size(); ++k)
    {
        const Triangle& t = m_triangles[k];
        Vec3 low = from[t[0]].cwiseMin(from[t[1]]).cwiseMin(from[t[2]]);
        Vec3 high = from[t[0]].cwiseMax(from[t[1]]).cwiseMax(from[t[2]]);
        if (&to != &from)
        {
            low = low.cwiseMin(to[t[0]]).cwiseMin(to[t[1]]).cwiseMin(to[t[2]]);
            high = high.cwiseMax(to[t[0]]).cwiseMax(to[t[1]]).cwiseMax(to[t[2]]);
        }
        m_low[k] = low;
        m_high[k] = high;
        const Real margin = std::max({reach[t[0]], reach[t[1]], reach[t[2]]}) + radius;
        const btDbvtVolume needed = selfContactBox(low, high, margin);
        if (!m_leaves[k])
        {
            m_leaves[k] = m_tree->insert(selfContactBox(low, high, margin + 0.25 * radius),
                                         reinterpret_cast<void*>(static_cast<std::uintptr_t>(k)));
            m_flatIsCurrent = false;
            continue;
        }
        const btDbvtVolume& stored = m_leaves[k]->volume;
        const bool tooLoose = stored.Lengths().length2() > 4 * needed.Lengths().length2();
        if (!stored.Contain(needed) || tooLoose)
        {
            btDbvtVolume fat = selfContactBox(low, high, margin + 0.25 * radius);
            m_tree->update(m_leaves[k], fat);
            m_flatIsCurrent = false;
        }
    }
}

bool SelfContactTree::withinReach(const std::vector<Vec3>& x, const std::vector<Real>& reach, Real radius, Index v,
                                  Index triangle) const
{
    // Most pairs whose boxes overlap are farther apart (box metric, fat boxes). The distance to the triangle's box, a
    // bound from below, turns most of them away before the closest point is sought.
    const Triangle& t = m_triangles[triangle];
    const Real limit = radius + reach[v] + std::max({reach[t[0]], reach[t[1]], reach[t[2]]});
    const Vec3& p = x[v];
    const Vec3 outside = (m_low[triangle] - p).cwiseMax(p - m_high[triangle]).cwiseMax(Vec3::Zero());
    return outside.squaredNorm() < limit * limit &&
           (p - closestPointOnTriangle(p, x[t[0]], x[t[1]], x[t[2]])).squaredNorm() < limit * limit;
}

void SelfContactTree::flatten()
{
    // The copy is a function of the tree alone: a sheet at rest, or the exclusions' lists batch after batch over the
    // rest positions, refit no leaf, and copying the tree again (11 ms at 128x2x128) would give the same nodes.
    if (m_flatIsCurrent)
    {
        return;
    }
    m_flatIsCurrent = true;
    // Preorder, the second child first: the order in which btDbvt::collideTV's stack visits the nodes, so a walk of
    // the copy meets the leaves in the order Bullet's own query would.
    m_flat.clear();
    m_walk.clear();
    if (m_tree->m_root)
    {
        m_walk.push_back(m_tree->m_root);
    }
    std::vector<std::size_t> open;      // flattened internal nodes whose subtree is still being copied
    std::vector<std::size_t> remaining; // per open node, its children not yet copied
    while (!m_walk.empty())
    {
        const btDbvtNode* node = m_walk.back();
        m_walk.pop_back();
        FlatNode flat;
        const btVector3& low = node->volume.Mins();
        const btVector3& high = node->volume.Maxs();
        flat.low = {low.x(), low.y(), low.z()};
        flat.high = {high.x(), high.y(), high.z()};
        if (node->isleaf())
        {
            flat.triangle = std::int32_t(reinterpret_cast<std::uintptr_t>(node->data));
        }
        else
        {
            m_walk.push_back(node->childs[0]);
            m_walk.push_back(node->childs[1]);
        }
        m_flat.push_back(flat);
        if (!node->isleaf())
        {
            open.push_back(m_flat.size() - 1);
            remaining.push_back(2);
            continue;
        }
        // A leaf closes every subtree it completes: their walks skip to the next node copied.
        m_flat.back().skip = std::uint32_t(m_flat.size());
        while (!open.empty() && --remaining.back() == 0)
        {
            m_flat[open.back()].skip = std::uint32_t(m_flat.size());
            open.pop_back();
            remaining.pop_back();
        }
    }
}

void SelfContactTree::boundArrivals(const std::vector<Vec3>& from, const std::vector<Vec3>& velocity)
{
    // Children come after their node in the flattened order, so one pass from the back has both of a node's children
    // bounded before it: the first at k + 1, the second where the first's subtree ends.
    m_nodeLow.resize(m_flat.size());
    m_nodeHigh.resize(m_flat.size());
    m_nodeVelocityLow.resize(m_flat.size());
    m_nodeVelocityHigh.resize(m_flat.size());
    for (std::size_t k = m_flat.size(); k-- > 0;)
    {
        if (m_flat[k].triangle >= 0)
        {
            const Triangle& t = m_triangles[std::size_t(m_flat[k].triangle)];
            m_nodeLow[k] = from[t[0]].cwiseMin(from[t[1]]).cwiseMin(from[t[2]]);
            m_nodeHigh[k] = from[t[0]].cwiseMax(from[t[1]]).cwiseMax(from[t[2]]);
            m_nodeVelocityLow[k] = velocity[t[0]].cwiseMin(velocity[t[1]]).cwiseMin(velocity[t[2]]);
            m_nodeVelocityHigh[k] = velocity[t[0]].cwiseMax(velocity[t[1]]).cwiseMax(velocity[t[2]]);
            continue;
        }
        const std::size_t first = k + 1;
        const std::size_t second = m_flat[first].skip;
        m_nodeLow[k] = m_nodeLow[first].cwiseMin(m_nodeLow[second]);
        m_nodeHigh[k] = m_nodeHigh[first].cwiseMax(m_nodeHigh[second]);
        m_nodeVelocityLow[k] = m_nodeVelocityLow[first].cwiseMin(m_nodeVelocityLow[second]);
        m_nodeVelocityHigh[k] = m_nodeVelocityHigh[first].cwiseMax(m_nodeVelocityHigh[second]);
    }
}

void SelfContactTree::boundMoves(const std::vector<Real>& reach)
{
    // As boundArrivals: one pass from the back, each node after both its children.
    m_nodeEndLow.resize(m_flat.size());
    m_nodeEndHigh.resize(m_flat.size());
    m_nodeMoveLow.resize(m_flat.size());
    m_nodeMoveHigh.resize(m_flat.size());
    m_nodeReach.resize(m_flat.size());
    for (std::size_t k = m_flat.size(); k-- > 0;)
    {
        if (m_flat[k].triangle >= 0)
        {
            const std::size_t triangle = std::size_t(m_flat[k].triangle);
            const Triangle& t = m_triangles[triangle];
            m_nodeEndLow[k] = m_endLow[triangle];
            m_nodeEndHigh[k] = m_endHigh[triangle];
            m_nodeMoveLow[k] = m_moveLow[triangle];
            m_nodeMoveHigh[k] = m_moveHigh[triangle];
            m_nodeReach[k] = std::max({reach[t[0]], reach[t[1]], reach[t[2]]});
            continue;
        }
        const std::size_t first = k + 1;
        const std::size_t second = m_flat[first].skip;
        m_nodeEndLow[k] = m_nodeEndLow[first].cwiseMin(m_nodeEndLow[second]);
        m_nodeEndHigh[k] = m_nodeEndHigh[first].cwiseMax(m_nodeEndHigh[second]);
        m_nodeMoveLow[k] = m_nodeMoveLow[first].cwiseMin(m_nodeMoveLow[second]);
        m_nodeMoveHigh[k] = m_nodeMoveHigh[first].cwiseMax(m_nodeMoveHigh[second]);
        m_nodeReach[k] = std::max(m_nodeReach[first], m_nodeReach[second]);
    }
}

template <class BoxOf, class GroupReach, class Accept>
void SelfContactTree::collectPairs(const std::vector<Index>& vertices, const SelfContactExclusions& excluded,
                                   const BoxOf& boxOf, const GroupReach& groupReach, const Accept& accept,
                                   std::vector<SelfContactPair>& out)
{
    const std::size_t ranges = chunkCount(vertices.size(), selfQueryChunkSize);
    m_rangePairs.reserveChunks(ranges);
    const std::size_t triangleCount = m_triangles.size();
    static_assert(selfQueryChunkSize % selfQueryGroupSize == 0, "a group never straddles two ranges");
    parallelFor(vertices.size(), selfQueryChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    std::vector<SelfContactPair>& pairs = m_rangePairs[begin / selfQueryChunkSize];
                    pairs.clear();
                    thread_local ExclusionMarks marks;
                    std::vector<std::uint32_t> leaves; // into m_flat
                    std::array<btDbvtVolume, selfQueryGroupSize> boxes;
                    for (std::size_t first = begin; first < end; first += selfQueryGroupSize)
                    {
                        const std::size_t count = std::min(selfQueryGroupSize, end - first);
                        for (std::size_t g = 0; g < count; ++g)
                        {
                            boxes[g] = boxOf(vertices[first + g]);
                        }
                        btDbvtVolume group = boxes[0];
                        for (std::size_t g = 1; g < count; ++g)
                        {
                            Merge(group, boxes[g], group);
                        }
                        const auto reaches = groupReach(&vertices[first], count);
                        leaves.clear();
                        for (std::uint32_t k = 0; k < m_flat.size();)
                        {
                            const FlatNode& node = m_flat[k];
                            if (!overlaps(node, group) || !reaches(k))
                            {
                                k = node.skip;
                                continue;
                            }
                            if (node.triangle >= 0)
                            {
                                leaves.push_back(k);
                            }
                            ++k;
                        }
                        // The group's leaves come in the walk's fixed order and hold every leaf of each vertex's own
                        // query, so each vertex's pairs are exactly, and in the order, that query would give. The
                        // tree is built and refitted on one thread from the same boxes in the same order, so the
                        // order is the same at any thread count.
                        for (std::size_t g = 0; g < count; ++g)
                        {
                            const Index v = vertices[first + g];
                            marks.mark(excluded, v, triangleCount);
                            for (const std::uint32_t k : leaves)
                            {
                                const Index triangle = Index(m_flat[k].triangle);
                                if (overlaps(m_flat[k], boxes[g]) && !marks.marked(triangle) &&
                                    accept(v, boxes[g], triangle, k))
                                {
                                    pairs.push_back({v, triangle});
                                }
                            }
                        }
                    }
                });
    out.clear();
    for (std::size_t range = 0; range < ranges; ++range)
    {
        out.insert(out.end(), m_rangePairs[range].begin(), m_rangePairs[range].end());
    }
}

inline bool SelfContactTree::sweptBoxesOverlap(const std::vector<Real>& reach, Real radius,
                                               const btDbvtVolume& vertexBox, Index triangle) const
{
    // The leaves are fat boxes: a pair is kept only if the vertex's box overlaps the triangle's own, grown by the
    // radius and its masses' largest reach.
    const Triangle& t = m_triangles[triangle];
    const Real margin = radius + std::max({reach[t[0]], reach[t[1]], reach[t[2]]});
    return Intersect(selfContactBox(m_low[triangle], m_high[triangle], margin), vertexBox);
}

void SelfContactTree::measureMoves(const std::vector<Vec3>& from, const std::vector<Vec3>& to)
{
    m_endLow.resize(m_triangles.size());
    m_endHigh.resize(m_triangles.size());
    m_moveLow.resize(m_triangles.size());
    m_moveHigh.resize(m_triangles.size());
    parallelFor(m_triangles.size(), selfQueryChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    for (std::size_t k = begin; k < end; ++k)
                    {
                        const Triangle& t = m_triangles[k];
                        m_endLow[k] = to[t[0]].cwiseMin(to[t[1]]).cwiseMin(to[t[2]]);
                        m_endHigh[k] = to[t[0]].cwiseMax(to[t[1]]).cwiseMax(to[t[2]]);
                        const Vec3 move0 = to[t[0]] - from[t[0]];
                        const Vec3 move1 = to[t[1]] - from[t[1]];
                        const Vec3 move2 = to[t[2]] - from[t[2]];
                        m_moveLow[k] = move0.cwiseMin(move1).cwiseMin(move2);
                        m_moveHigh[k] = move0.cwiseMax(move1).cwiseMax(move2);
                    }
                });
}

inline bool SelfContactTree::mayComeNear(const std::vector<Vec3>& from, const std::vector<Vec3>& to,
                                         const std::vector<Real>& reach, Real radius, Index v, Index triangle) const
{
    // At a moment s of the motion the vertex is within the radius of a point of the triangle; from there to the
    // motion's end each of the triangle's masses moves by (1 - s) times its move, the vertex by (1 - s) times its
    // own, and each strays at most its reach from its line. So at `to`, along every axis, the vertex lies within the
    // radius, the reaches and the largest difference of moves of the triangle's box; sweptFrameAllowance radii more
    // for what moves the masses after the list. Two masses moving side by side or one behind the other are not
    // listed, however fast; a billionth of the radius to spare for rounding.
    const Triangle& t = m_triangles[triangle];
    const Vec3 move = to[v] - from[v];
    const Real gap = (m_endLow[triangle] - to[v]).cwiseMax(to[v] - m_endHigh[triangle]).maxCoeff();
    const Real moves = (m_moveHigh[triangle] - move).cwiseMax(move - m_moveLow[triangle]).maxCoeff();
    const Real reaches = reach[v] + std::max({reach[t[0]], reach[t[1]], reach[t[2]]});
    return gap <= (1 + sweptFrameAllowance) * radius + reaches + moves + Real(1e-9) * radius;
}

void SelfContactTree::findPairs(const std::vector<Vec3>& x, const std::vector<Real>& reach, Real radius,
                                const std::vector<Index>& vertices, const SelfContactExclusions& excluded,
                                std::vector<SelfContactPair>& out)
{
    refit(x, x, reach, radius);
    flatten();
    collectPairs(
        vertices, excluded, [&](Index v) { return selfContactBox(x[v], x[v], reach[v]); }, everyNode,
        [&](Index v, const btDbvtVolume& /*box*/, Index triangle, std::uint32_t /*node*/)
        { return withinReach(x, reach, radius, v, triangle); },
        out);
}

void SelfContactTree::findSweptPairs(const std::vector<Vec3>& from, const std::vector<Vec3>& to,
                                     const std::vector<Real>& reach, Real radius, const std::vector<Index>& vertices,
                                     const SelfContactExclusions& excluded, std::vector<SelfContactPair>& out)
{
    refit(from, to, reach, radius);
    flatten();
    measureMoves(from, to);
    boundMoves(reach);
    // A group of vertices skips a subtree when even the nearest of its boxes at `to` and the most different of its
    // moves, against the group's, leave no pair that mayComeNear takes. The bound's sums are those of mayComeNear
    // over boxes that hold the pairs' own, so rounding never lets it turn away a pair the exact test keeps.
    const auto groupReach = [&](const Index* group, std::size_t count)
    {
        Vec3 low = to[group[0]];
        Vec3 high = low;
        Vec3 moveLow = to[group[0]] - from[group[0]];
        Vec3 moveHigh = moveLow;
        Real mostReach = reach[group[0]];
        for (std::size_t g = 1; g < count; ++g)
        {
            const Index v = group[g];
            low = low.cwiseMin(to[v]);
            high = high.cwiseMax(to[v]);
            moveLow = moveLow.cwiseMin(to[v] - from[v]);
            moveHigh = moveHigh.cwiseMax(to[v] - from[v]);
            mostReach = std::max(mostReach, reach[v]);
        }
        return [&, low, high, moveLow, moveHigh, mostReach](std::uint32_t k)
        {
            const Real gap = (m_nodeEndLow[k] - high).cwiseMax(low - m_nodeEndHigh[k]).maxCoeff();
            const Real moves = (m_nodeMoveHigh[k] - moveLow).cwiseMax(moveHigh - m_nodeMoveLow[k]).maxCoeff();
            return gap <=
                   (1 + sweptFrameAllowance) * radius + (mostReach + m_nodeReach[k]) + moves + Real(1e-9) * radius;
        };
    };
    collectPairs(
        vertices, excluded, [&](Index v) { return sweptBox(from, to, reach, v); }, groupReach,
        [&](Index v, const btDbvtVolume& box, Index triangle, std::uint32_t /*node*/) {
            return sweptBoxesOverlap(reach, radius, box, triangle) && mayComeNear(from, to, reach, radius, v, triangle);
        },
        out);
}

void SelfContactTree::findSweptArrivingPairs(const std::vector<Vec3>& from, const std::vector<Vec3>& to,
                                             const std::vector<Real>& reach, Real radius,
                                             const std::vector<Index>& vertices, const SelfContactExclusions& excluded,
                                             const ArrivalTest& arrival, std::vector<SelfContactPair>& out)
{
    refit(from, to, reach, radius);
    flatten();
    const std::vector<Vec3>& v = *arrival.velocity;
    boundArrivals(from, v);
    // A group of vertices skips a subtree when even the nearest of its boxes and the fastest of its velocities,
    // against the group's, would leave no pair the arrivals take: then none of its triangles' pairs passes the exact
    // test below. A billionth to spare, so that rounding in the bounds' different sums decides nothing.
    const Real spare = Real(1e-9);
    const auto groupReach = [&](const Index* group, std::size_t count)
    {
        Vec3 low = from[group[0]];
        Vec3 high = low;
        Vec3 velocityLow = v[group[0]];
        Vec3 velocityHigh = velocityLow;
        for (std::size_t g = 1; g < count; ++g)
        {
            low = low.cwiseMin(from[group[g]]);
            high = high.cwiseMax(from[group[g]]);
            velocityLow = velocityLow.cwiseMin(v[group[g]]);
            velocityHigh = velocityHigh.cwiseMax(v[group[g]]);
        }
        return [&, low, high, velocityLow, velocityHigh](std::uint32_t k)
        {
            const Vec3 outside = (m_nodeLow[k] - high).cwiseMax(low - m_nodeHigh[k]).cwiseMax(Vec3::Zero());
            const Vec3 apart = (m_nodeVelocityHigh[k] - velocityLow).cwiseMax(velocityHigh - m_nodeVelocityLow[k]);
            return arrival.mayArrive(outside.norm() - radius - spare * radius, apart.norm() * (1 + spare));
        };
    };
    collectPairs(
        vertices, excluded, [&](Index i) { return sweptBox(from, to, reach, i); }, groupReach,
        [&](Index i, const btDbvtVolume& box, Index triangle, std::uint32_t node)
        {
            // The arrivals' own test, on the triangle's box at `from` as they measure it (the leaf's, boundArrivals).
            return sweptBoxesOverlap(reach, radius, box, triangle) &&
                   arrival.mayArrive(gapToBox(from[i], m_nodeLow[node], m_nodeHigh[node], radius),
                                     arrival.relativeSpeed(i, m_triangles[triangle]));
        },
        out);
}
} // namespace masse::bridge
