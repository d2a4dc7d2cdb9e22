#pragma once
/// The broadphase of the sheet's self-contact, through Bullet: one btDbvt over the sheet's surface triangles with fat
/// boxes, refitted and queried by every surface vertex's box when the core lists its pairs (SelfContactBroadphase.h
/// says what the pairs mean): at each frame's start, and again within a frame only when a mass has moved beyond its
/// skin (SelfContact.h), or, under one solve a frame, by each vertex's box over its motion in the step (findSweptPairs:
/// at the frame's start and after the solve). Not every substep: a query per vertex per substep would cost 4.2 times
/// the step; the core tests the listed pairs after every substep.

#include "core/contact/SelfContactBroadphase.h"
#include "core/parallel/PerChunk.h"

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

class btDbvt;
struct btDbvtAabbMm;
struct btDbvtNode;

namespace masse::bridge
{
class SelfContactTree final : public SelfContactBroadphase
{
public:
    SelfContactTree();
    ~SelfContactTree() override;
    SelfContactTree(const SelfContactTree&) = delete;
    SelfContactTree& operator=(const SelfContactTree&) = delete;

    void setTriangles(const std::vector<Triangle>& triangles) override;
    void findPairs(const std::vector<Vec3>& x, const std::vector<Real>& reach, Real radius,
                   const std::vector<Index>& vertices, const SelfContactExclusions& excluded,
                   std::vector<SelfContactPair>& out) override;
    void findSweptPairs(const std::vector<Vec3>& from, const std::vector<Vec3>& to, const std::vector<Real>& reach,
                        Real radius, const std::vector<Index>& vertices, const SelfContactExclusions& excluded,
                        std::vector<SelfContactPair>& out) override;
    void findSweptArrivingPairs(const std::vector<Vec3>& from, const std::vector<Vec3>& to,
                                const std::vector<Real>& reach, Real radius, const std::vector<Index>& vertices,
                                const SelfContactExclusions& excluded, const ArrivalTest& arrival,
                                std::vector<SelfContactPair>& out) override;

    /// A node of the tree copied into one array in the order a walk visits it.
    struct FlatNode
    {
        std::array<Real, 3> low{};
        std::array<Real, 3> high{};
        std::uint32_t skip = 0;     ///< where a walk goes when the node's box misses: past its subtree
        std::int32_t triangle = -1; ///< a leaf's triangle; -1 for an inner node
    };

private:
    /// Copies the tree into m_flat, unless no leaf has moved since the last copy.
    void flatten();
    /// Whether vertex v is closer to the triangle than the radius plus v's reach plus its masses' largest.
    bool withinReach(const std::vector<Vec3>& x, const std::vector<Real>& reach, Real radius, Index v,
                     Index triangle) const;
    /// Each triangle's box over its masses at `from` and `to` (the same positions for a list at one moment), into
    /// m_low and m_high, and the tree's leaves grown to hold it plus the radius and its masses' largest reach.
    void refit(const std::vector<Vec3>& from, const std::vector<Vec3>& to, const std::vector<Real>& reach, Real radius);
    /// Each flattened node's bounds for findSweptArrivingPairs: the box of its triangles' masses at `from` and the box
    /// of their velocities.
    void boundArrivals(const std::vector<Vec3>& from, const std::vector<Vec3>& velocity);
    /// Whether a vertex's swept box overlaps the triangle's own (m_low, m_high), grown by the radius and its masses'
    /// largest reach.
    bool sweptBoxesOverlap(const std::vector<Real>& reach, Real radius, const btDbvtAabbMm& vertexBox,
                           Index triangle) const;
    /// Each triangle's box at `to` and the box of its masses' moves from `from` to `to`, into m_endLow, m_endHigh,
    /// m_moveLow and m_moveHigh.
    void measureMoves(const std::vector<Vec3>& from, const std::vector<Vec3>& to);
    /// Each flattened node's bounds for findSweptPairs: the box of its triangles' boxes at `to`, the box of their
    /// masses' moves, and their masses' largest reach (after measureMoves).
    void boundMoves(const std::vector<Real>& reach);
    /// Whether vertex v, in its own frame of motion from `from` to `to`, may come within the radius of the triangle:
    /// at `to` it lies within the radius, its own and the triangle's masses' largest reach, and the most the masses'
    /// moves differ from its own along an axis, of the triangle's box (measureMoves).
    bool mayComeNear(const std::vector<Vec3>& from, const std::vector<Vec3>& to, const std::vector<Real>& reach,
                     Real radius, Index v, Index triangle) const;
    /// The walks of the lists, over the flattened tree: each vertex's box (boxOf) against the tree, merged over a few
    /// vertices, down the nodes the merged box overlaps and groupReach(group, count) takes, and the pairs of the
    /// leaves it overlaps that the exclusions leave and accept(vertex, its box, triangle, leaf's flattened index)
    /// takes, in vertex order.
    template <class BoxOf, class GroupReach, class Accept>
    void collectPairs(const std::vector<Index>& vertices, const SelfContactExclusions& excluded, const BoxOf& boxOf,
                      const GroupReach& groupReach, const Accept& accept, std::vector<SelfContactPair>& out);

    std::unique_ptr<btDbvt> m_tree;
    std::vector<Triangle> m_triangles;
    std::vector<btDbvtNode*> m_leaves; ///< per triangle
    std::vector<Vec3> m_low;           ///< per triangle, its vertices' box at the last refit
    std::vector<Vec3> m_high;
    std::vector<Vec3> m_endLow; ///< per triangle, its box at the swept list's `to` (measureMoves)
    std::vector<Vec3> m_endHigh;
    std::vector<Vec3> m_moveLow; ///< per triangle, the box of its masses' moves in the swept list's motion
    std::vector<Vec3> m_moveHigh;
    std::vector<FlatNode> m_flat;   ///< the tree, flattened for the lists
    bool m_flatIsCurrent = false;   ///< no leaf inserted or moved since m_flat was copied
    std::vector<Vec3> m_nodeEndLow; ///< per flattened node, boundMoves' boxes and reach
    std::vector<Vec3> m_nodeEndHigh;
    std::vector<Vec3> m_nodeMoveLow;
    std::vector<Vec3> m_nodeMoveHigh;
    std::vector<Real> m_nodeReach;
    std::vector<Vec3> m_nodeLow; ///< per flattened node, boundArrivals' boxes
    std::vector<Vec3> m_nodeHigh;
    std::vector<Vec3> m_nodeVelocityLow;
    std::vector<Vec3> m_nodeVelocityHigh;
    std::vector<const btDbvtNode*> m_walk;               ///< flatten's stack
    PerChunk<std::vector<SelfContactPair>> m_rangePairs; ///< per range of vertices, reused frame to frame
};
} // namespace masse::bridge
