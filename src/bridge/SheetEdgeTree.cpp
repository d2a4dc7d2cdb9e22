#include "SheetEdgeTree.h"

#include "BulletMath.h"

#include "core/Format.h"
#include "core/NumericalError.h"
#include "core/contact/ClosestPointOnTriangle.h"
#include "core/contact/ClosestPointsOfSegments.h"
#include "core/parallel/TaskPool.h"

#include <BulletCollision/BroadphaseCollision/btDbvt.h>

#include <algorithm>
#include <cstdint>
#include <limits>

namespace masse::bridge
{
namespace
{
/// Features per range of the queries: few features, each query possibly meeting many triangles.
constexpr std::size_t featureChunkSize = 8;
/// Surface masses per range of the sheet's box.
constexpr std::size_t vertexChunkSize = 8192;
/// Patches (of up to 128 triangles) per range of the refit's boxes.
constexpr std::size_t patchChunkSize = 32;

/// Collects the patches (leaf data) whose boxes a feature's box overlaps.
struct PatchCollector final : btDbvt::ICollide
{
    std::vector<std::size_t>* out = nullptr;
    void Process(const btDbvtNode* leaf) override
    {
        out->push_back(std::size_t(reinterpret_cast<std::uintptr_t>(leaf->data)));
    }
};

btDbvtVolume boxOf(const Vec3& low, const Vec3& high)
{
    return btDbvtVolume::FromMM(toBullet(low), toBullet(high));
}

/// The farthest from the origin a patch's box may reach (m). Bullet's tree multiplies a box's three lengths
/// (btDbvt's size()) and adds its corners; past about 1e102 m they overflow, its splits go wrong, and a leaf ends up
/// in the tree twice (a double free when it is cleared). A sheet that far away has diverged whatever the scene.
constexpr Real largestBoxCoordinate = 1e100;
} // namespace

SheetEdgeTree::SheetEdgeTree(const BulletEnvironment& environment)
    : m_environment(environment), m_tree(std::make_unique<btDbvt>())
{
}

SheetEdgeTree::~SheetEdgeTree() = default;

void SheetEdgeTree::setSurface(const SheetSurface& surface)
{
    m_tree->clear();
    m_surface = surface;
    const std::size_t patches = m_surface.patchStart.empty() ? 0 : m_surface.patchStart.size() - 1;
    m_leaves.assign(patches, nullptr);
    m_internalNodes.clear();
    m_low.resize(patches);
    m_high.resize(patches);
}

void SheetEdgeTree::triangleBox(const std::vector<Vec3>& x, const std::vector<Real>& reach, Real radius, Index triangle,
                                Vec3& low, Vec3& high) const
{
    const Triangle& t = m_surface.triangles[triangle];
    const Vec3 grow = Vec3::Constant(std::max({reach[t[0]], reach[t[1]], reach[t[2]]}) + radius);
    low = x[t[0]].cwiseMin(x[t[1]]).cwiseMin(x[t[2]]) - grow;
    high = x[t[0]].cwiseMax(x[t[1]]).cwiseMax(x[t[2]]) + grow;
}

void SheetEdgeTree::build()
{
    // Inserted one by one, then rebuilt from the top down (Bullet's split along the longest axis of the leaves'
    // centres): a tree of the sheet as it lies now, whose subtrees are pieces of it.
    for (std::size_t k = 0; k < m_leaves.size(); ++k)
    {
        m_leaves[k] =
            m_tree->insert(boxOf(m_low[k], m_high[k]), reinterpret_cast<void*>(static_cast<std::uintptr_t>(k)));
    }
    m_tree->optimizeTopDown();
    // The internal nodes, each after its children: the reverse of a walk that visits a node before its children.
    std::vector<btDbvtNode*> stack;
    if (m_tree->m_root && m_tree->m_root->isinternal())
    {
        stack.push_back(m_tree->m_root);
    }
    while (!stack.empty())
    {
        btDbvtNode* node = stack.back();
        stack.pop_back();
        m_internalNodes.push_back(node);
        for (btDbvtNode* child : node->childs)
        {
            if (child->isinternal())
            {
                stack.push_back(child);
            }
        }
    }
    std::reverse(m_internalNodes.begin(), m_internalNodes.end());
}

void SheetEdgeTree::refit(const std::vector<Vec3>& x, const std::vector<Real>& reach, Real radius, Real time)
{
    // Each patch's box: its triangles' boxes, grown by their masses' reach and the radius.
    parallelFor(m_leaves.size(), patchChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    for (std::size_t k = begin; k < end; ++k)
                    {
                        Vec3 low = Vec3::Constant(std::numeric_limits<Real>::infinity());
                        Vec3 high = -low;
                        for (std::size_t j = m_surface.patchStart[k]; j < m_surface.patchStart[k + 1]; ++j)
                        {
                            Vec3 triangleLow, triangleHigh;
                            triangleBox(x, reach, radius, m_surface.patchTriangles[j], triangleLow, triangleHigh);
                            low = low.cwiseMin(triangleLow);
                            high = high.cwiseMax(triangleHigh);
                        }
                        m_low[k] = low;
                        m_high[k] = high;
                    }
                });
    for (std::size_t k = 0; k < m_leaves.size(); ++k)
    {
        // Written so that a NaN fails it too.
        if (!(m_low[k].cwiseAbs().maxCoeff() <= largestBoxCoordinate) ||
            !(m_high[k].cwiseAbs().maxCoeff() <= largestBoxCoordinate))
        {
            throwDiverged(x, reach, k, time);
        }
    }
    if (!m_tree->m_root)
    {
        build();
        return;
    }
    for (std::size_t k = 0; k < m_leaves.size(); ++k)
    {
        m_leaves[k]->volume = boxOf(m_low[k], m_high[k]);
    }
    for (btDbvtNode* node : m_internalNodes)
    {
        Merge(node->childs[0]->volume, node->childs[1]->volume, node->volume);
    }
}

void SheetEdgeTree::throwDiverged(const std::vector<Vec3>& x, const std::vector<Real>& reach, std::size_t patch,
                                  Real time) const
{
    // The patch's mass that reaches farthest (its position, or its reach over the step): the one to name.
    Index farthest = m_surface.triangles[m_surface.patchTriangles[m_surface.patchStart[patch]]][0];
    Real distance = -1;
    for (std::size_t j = m_surface.patchStart[patch]; j < m_surface.patchStart[patch + 1]; ++j)
    {
        for (const Index m : m_surface.triangles[m_surface.patchTriangles[j]])
        {
            const Real d = x[m].cwiseAbs().maxCoeff() + reach[m];
            if (!(d <= distance))
            {
                farthest = m;
                distance = d;
            }
        }
    }
    throw NumericalError("the simulation diverged at t = " + formatNumber(time) + " s: mass " +
                         std::to_string(farthest) + " is at " + formatNumber(x[farthest].cwiseAbs().maxCoeff()) +
                         " m from the origin and may move " + formatNumber(reach[farthest]) +
                         " m in a step, beyond what the edge contact can follow (" +
                         formatNumber(largestBoxCoordinate) + " m)");
}

Real SheetEdgeTree::clearance(const std::vector<Vec3>& x, const std::vector<Real>& reach, Real radius, Real span,
                              const EdgeContactCandidates& out)
{
    const std::vector<Index>& vertices = m_surface.vertices;
    m_chunkLow.resize(chunkCount(vertices.size(), vertexChunkSize));
    m_chunkHigh.resize(m_chunkLow.size());
    parallelFor(vertices.size(), vertexChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    Vec3 low = Vec3::Constant(std::numeric_limits<Real>::infinity());
                    Vec3 high = -low;
                    for (std::size_t k = begin; k < end; ++k)
                    {
                        const Vec3 grow = Vec3::Constant(reach[vertices[k]] + radius);
                        low = low.cwiseMin(x[vertices[k]] - grow);
                        high = high.cwiseMax(x[vertices[k]] + grow);
                    }
                    m_chunkLow[begin / vertexChunkSize] = low;
                    m_chunkHigh[begin / vertexChunkSize] = high;
                });
    Vec3 low = Vec3::Constant(std::numeric_limits<Real>::infinity());
    Vec3 high = -low;
    for (std::size_t chunk = 0; chunk < m_chunkLow.size(); ++chunk)
    {
        low = low.cwiseMin(m_chunkLow[chunk]);
        high = high.cwiseMax(m_chunkHigh[chunk]);
    }
    // The gap between two boxes: the length of their separation along each axis (0 where they overlap).
    const auto gap = [&](const Vec3& featureLow, const Vec3& featureHigh)
    { return (featureLow - high).cwiseMax(low - featureHigh).cwiseMax(Vec3::Zero()).norm(); };
    Real smallest = std::numeric_limits<Real>::infinity();
    for (const ObstacleEdge& edge : out.edges)
    {
        const Vec3 startLater = edge.start + span * edge.startVelocity;
        const Vec3 endLater = edge.end + span * edge.endVelocity;
        smallest = std::min(smallest, gap(edge.start.cwiseMin(edge.end).cwiseMin(startLater).cwiseMin(endLater),
                                          edge.start.cwiseMax(edge.end).cwiseMax(startLater).cwiseMax(endLater)));
    }
    for (const ObstacleCorner& corner : out.corners)
    {
        const Vec3 later = corner.point + span * corner.velocity;
        smallest = std::min(smallest, gap(corner.point.cwiseMin(later), corner.point.cwiseMax(later)));
    }
    return smallest;
}

void SheetEdgeTree::trianglesMeeting(const std::vector<Vec3>& x, const std::vector<Real>& reach, Real radius,
                                     const Vec3& low, const Vec3& high, ChunkPairs& chunk) const
{
    PatchCollector collector;
    collector.out = &chunk.patches;
    chunk.patches.clear();
    m_tree->collideTV(m_tree->m_root, boxOf(low, high), collector);
    chunk.found.clear();
    for (const std::size_t patch : chunk.patches)
    {
        for (std::size_t j = m_surface.patchStart[patch]; j < m_surface.patchStart[patch + 1]; ++j)
        {
            const Index t = m_surface.patchTriangles[j];
            Vec3 triangleLow, triangleHigh;
            triangleBox(x, reach, radius, t, triangleLow, triangleHigh);
            if ((triangleLow.array() <= high.array()).all() && (triangleHigh.array() >= low.array()).all())
            {
                chunk.found.push_back(t);
            }
        }
    }
    std::sort(chunk.found.begin(), chunk.found.end());
}

void SheetEdgeTree::placeFeatures(Real time, Real dt, EdgeContactCandidates& out)
{
    const int obstacles = m_environment.obstacleCount();
    for (int index = int(m_features.size()); index < obstacles; ++index)
    {
        const Obstacle& obstacle = m_environment.obstacle(index);
        m_features.push_back(obstacle.partOfRoom ? SharpFeatures{} : sharpFeatures(obstacle.geometry));
    }
    out.edges.clear();
    out.corners.clear();
    out.cornerNormals.clear();
    for (int index = 0; index < obstacles; ++index)
    {
        const SharpFeatures& features = m_features[std::size_t(index)];
        if (features.edges.empty() && features.corners.empty())
        {
            continue;
        }
        const Obstacle& obstacle = m_environment.obstacle(index);
        const Pose pose = poseAt(obstacle.path, time);
        const Motion motion =
            obstacle.path.isKinematic() && dt > 0 ? averageMotion(obstacle.path, time, time + dt) : Motion{};
        const auto place = [&](int vertex)
        { return Vec3(pose.orientation * obstacle.geometry.vertices[std::size_t(vertex)] + pose.position); };
        for (const SharpEdge& local : features.edges)
        {
            ObstacleEdge edge;
            edge.start = place(local.start);
            edge.end = place(local.end);
            edge.startVelocity = motion.at(edge.start, pose.position);
            edge.endVelocity = motion.at(edge.end, pose.position);
            edge.normals[0] = pose.orientation * local.normals[0];
            edge.normals[1] = pose.orientation * local.normals[1];
            edge.obstacle = index;
            out.edges.push_back(edge);
        }
        for (const SharpCorner& local : features.corners)
        {
            ObstacleCorner corner;
            corner.point = place(local.vertex);
            corner.velocity = motion.at(corner.point, pose.position);
            corner.firstNormal = std::uint32_t(out.cornerNormals.size());
            corner.normalCount = std::uint32_t(local.normalCount);
            for (std::size_t n = local.firstNormal; n < local.firstNormal + local.normalCount; ++n)
            {
                out.cornerNormals.push_back(pose.orientation * features.cornerNormals[n]);
            }
            corner.obstacle = index;
            out.corners.push_back(corner);
        }
    }
}

void SheetEdgeTree::findCandidates(const std::vector<Vec3>& x, const std::vector<Real>& reach, Real radius, Real time,
                                   Real dt, EdgeContactCandidates& out)
{
    placeFeatures(time, dt, out);
    out.edgePairs.clear();
    out.cornerPairs.clear();
    out.clearance = std::numeric_limits<Real>::infinity();
    const std::size_t features = out.edges.size() + out.corners.size();
    if (features == 0 || m_leaves.empty())
    {
        return;
    }
    // The sheet's box first, a pass over its masses: a sheet clear of every feature's box (the common case, falling
    // or lying away from any edge) needs no refit and no query.
    out.clearance = clearance(x, reach, radius, std::max(dt, Real(0)), out);
    if (out.clearance > 0)
    {
        return;
    }
    refit(x, reach, radius, time);
    const std::size_t chunks = chunkCount(features, featureChunkSize);
    m_chunks.reserveChunks(chunks);
    const Real span = std::max(dt, Real(0));
    parallelFor(features, featureChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    ChunkPairs& chunk = m_chunks[begin / featureChunkSize];
                    chunk.edgePairs.clear();
                    chunk.cornerPairs.clear();
                    for (std::size_t f = begin; f < end; ++f)
                    {
                        if (f < out.edges.size())
                        {
                            listEdge(x, reach, radius, span, out, Index(f), chunk);
                        }
                        else
                        {
                            listCorner(x, reach, radius, span, out, Index(f - out.edges.size()), chunk);
                        }
                    }
                });
    for (std::size_t chunk = 0; chunk < chunks; ++chunk)
    {
        out.edgePairs.insert(out.edgePairs.end(), m_chunks[chunk].edgePairs.begin(), m_chunks[chunk].edgePairs.end());
        out.cornerPairs.insert(out.cornerPairs.end(), m_chunks[chunk].cornerPairs.begin(),
                               m_chunks[chunk].cornerPairs.end());
    }
}

void SheetEdgeTree::listEdge(const std::vector<Vec3>& x, const std::vector<Real>& reach, Real radius, Real span,
                             const EdgeContactCandidates& out, Index f, ChunkPairs& chunk) const
{
    // The edge's box over the frame meets the boxes of the triangles whose masses' reach and the radius take them
    // near it; their edges are kept when they are that near the edge.
    const ObstacleEdge& edge = out.edges[f];
    const Vec3 startLater = edge.start + span * edge.startVelocity;
    const Vec3 endLater = edge.end + span * edge.endVelocity;
    trianglesMeeting(x, reach, radius, edge.start.cwiseMin(edge.end).cwiseMin(startLater).cwiseMin(endLater),
                     edge.start.cwiseMax(edge.end).cwiseMax(startLater).cwiseMax(endLater), chunk);
    chunk.edges.clear();
    for (const Index t : chunk.found)
    {
        chunk.edges.insert(chunk.edges.end(), m_surface.triangleEdges[t].begin(), m_surface.triangleEdges[t].end());
    }
    std::sort(chunk.edges.begin(), chunk.edges.end());
    chunk.edges.erase(std::unique(chunk.edges.begin(), chunk.edges.end()), chunk.edges.end());
    const Real travel = span * std::max(edge.startVelocity.norm(), edge.endVelocity.norm()) + radius;
    for (const Index e : chunk.edges)
    {
        const Edge& sheet = m_surface.edges[e];
        const SegmentParameters at = closestPointsOfSegments(x[sheet[0]], x[sheet[1]], edge.start, edge.end);
        const Vec3 gap =
            x[sheet[0]] + at.s * (x[sheet[1]] - x[sheet[0]]) - (edge.start + at.t * (edge.end - edge.start));
        const Real within = travel + std::max(reach[sheet[0]], reach[sheet[1]]);
        if (gap.squaredNorm() <= within * within)
        {
            chunk.edgePairs.push_back({e, f});
        }
    }
}

void SheetEdgeTree::listCorner(const std::vector<Vec3>& x, const std::vector<Real>& reach, Real radius, Real span,
                               const EdgeContactCandidates& out, Index c, ChunkPairs& chunk) const
{
    const ObstacleCorner& corner = out.corners[c];
    const Vec3 later = corner.point + span * corner.velocity;
    trianglesMeeting(x, reach, radius, corner.point.cwiseMin(later), corner.point.cwiseMax(later), chunk);
    const Real travel = span * corner.velocity.norm() + radius;
    for (const Index t : chunk.found)
    {
        const Triangle& triangle = m_surface.triangles[t];
        const Vec3 gap =
            corner.point - closestPointOnTriangle(corner.point, x[triangle[0]], x[triangle[1]], x[triangle[2]]);
        const Real within = travel + std::max({reach[triangle[0]], reach[triangle[1]], reach[triangle[2]]});
        if (gap.squaredNorm() <= within * within)
        {
            chunk.cornerPairs.push_back({t, c});
        }
    }
}
} // namespace masse::bridge
