#include "SelfContactTree.h"

#include "BulletMath.h"

#include "core/TaskPool.h"

#include <BulletCollision/BroadphaseCollision/btDbvt.h>

#include <algorithm>
#include <cstdint>

namespace masse::bridge
{
namespace
{
/// Surface vertices per range of the queries: the pairs gather where the sheet folds, and small ranges let the
/// threads share that part evenly.
constexpr std::size_t selfQueryChunkSize = 512;

/// Collects the triangles (leaf data) whose boxes a vertex's box overlaps.
struct SurfaceTriangleCollector final : btDbvt::ICollide
{
    std::vector<SelfContactPair>* out = nullptr;
    Index vertex = 0;
    void Process(const btDbvtNode* leaf) override
    {
        out->push_back({vertex, Index(reinterpret_cast<std::uintptr_t>(leaf->data))});
    }
};

btDbvtVolume selfContactBox(const Vec3& low, const Vec3& high, Real margin)
{
    const Vec3 grow = Vec3::Constant(margin);
    return btDbvtVolume::FromMM(toBullet(low - grow), toBullet(high + grow));
}
} // namespace

SelfContactTree::SelfContactTree() : m_tree(std::make_unique<btDbvt>()) {}

SelfContactTree::~SelfContactTree() = default;

void SelfContactTree::setTriangles(const std::vector<Triangle>& triangles)
{
    m_tree->clear();
    m_triangles = triangles;
    m_leaves.assign(triangles.size(), nullptr);
}

void SelfContactTree::refit(const std::vector<Vec3>& x, const std::vector<Real>& reach, Real radius)
{
    // A leaf's box is the triangle's box grown by the farthest its masses may move this frame plus the radius. A leaf
    // whose stored box still holds that stays as it is; one that does not (or has grown past twice the box it needs,
    // after the sheet slowed down) is reinserted with a fat box, grown by another quarter radius, so a sheet in slow
    // motion rebuilds little of the tree from list to list.
    for (std::size_t k = 0; k < m_triangles.size(); ++k)
    {
        const Triangle& t = m_triangles[k];
        const Vec3 low = x[t[0]].cwiseMin(x[t[1]]).cwiseMin(x[t[2]]);
        const Vec3 high = x[t[0]].cwiseMax(x[t[1]]).cwiseMax(x[t[2]]);
        const Real margin = std::max({reach[t[0]], reach[t[1]], reach[t[2]]}) + radius;
        const btDbvtVolume needed = selfContactBox(low, high, margin);
        if (!m_leaves[k])
        {
            m_leaves[k] = m_tree->insert(selfContactBox(low, high, margin + 0.25 * radius),
                                         reinterpret_cast<void*>(static_cast<std::uintptr_t>(k)));
            continue;
        }
        const btDbvtVolume& stored = m_leaves[k]->volume;
        const bool tooLoose = stored.Lengths().length2() > 4 * needed.Lengths().length2();
        if (!stored.Contain(needed) || tooLoose)
        {
            btDbvtVolume fat = selfContactBox(low, high, margin + 0.25 * radius);
            m_tree->update(m_leaves[k], fat);
        }
    }
}

void SelfContactTree::findPairs(const std::vector<Vec3>& x, const std::vector<Real>& reach, Real radius,
                                const std::vector<Index>& vertices, std::vector<SelfContactPair>& out)
{
    refit(x, reach, radius);
    const std::size_t ranges = chunkCount(vertices.size(), selfQueryChunkSize);
    if (m_rangePairs.size() < ranges)
    {
        m_rangePairs.resize(ranges);
    }
    const btDbvt& tree = *m_tree;
    parallelFor(vertices.size(), selfQueryChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    std::vector<SelfContactPair>& pairs = m_rangePairs[begin / selfQueryChunkSize];
                    pairs.clear();
                    SurfaceTriangleCollector collector;
                    collector.out = &pairs;
                    for (std::size_t i = begin; i < end; ++i)
                    {
                        const Index v = vertices[i];
                        collector.vertex = v;
                        tree.collideTV(tree.m_root, selfContactBox(x[v], x[v], reach[v]), collector);
                        // In the tree's order, not sorted: the tree is built and refitted on one thread from
                        // the same boxes in the same order, so its order is the same at any thread count.
                    }
                });
    out.clear();
    for (std::size_t range = 0; range < ranges; ++range)
    {
        out.insert(out.end(), m_rangePairs[range].begin(), m_rangePairs[range].end());
    }
}
} // namespace masse::bridge
