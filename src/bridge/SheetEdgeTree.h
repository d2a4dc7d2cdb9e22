#pragma once
/// The broadphase of the sheet's edge contact, through Bullet: a btDbvt over the sheet's surface triangles, a leaf per
/// patch of 8 x 8 cells (SheetSurface), built once from the sheet as it first lies (a patch, and a subtree over
/// neighbouring patches, stays a compact piece of the sheet however it folds) and refitted from the leaves up at every
/// listing, no leaf reinserted. Every sharp edge and corner of every obstacle
/// (ObstacleFeatures.h; the room's walls are left out) is a query of the tree with its box over the frame; the
/// triangles it meets give their edges (for an edge) or themselves (for a corner), kept when their distance at the
/// listing is within the radius plus what both can move (core's closed forms). EdgeContactDetector.h says what the
/// lists mean.
///
/// When no obstacle feature's box meets the sheet's (grown by every mass's reach and the radius), a listing costs one
/// pass over the surface's masses for that box, on every thread; otherwise the refit (each triangle's box, and one
/// merge per patch) and the queries.

#include "BulletEnvironment.h"
#include "ObstacleFeatures.h"

#include "core/contact/EdgeContactDetector.h"
#include "core/parallel/PerChunk.h"

#include <memory>
#include <vector>

class btDbvt;
struct btDbvtNode;

namespace masse::bridge
{
class SheetEdgeTree final : public EdgeContactDetector
{
public:
    explicit SheetEdgeTree(const BulletEnvironment& environment);
    ~SheetEdgeTree() override;
    SheetEdgeTree(const SheetEdgeTree&) = delete;
    SheetEdgeTree& operator=(const SheetEdgeTree&) = delete;

    void setSurface(const SheetSurface& surface) override;
    void findCandidates(const std::vector<Vec3>& x, const std::vector<Real>& reach, Real radius, Real time, Real dt,
                        EdgeContactCandidates& out) override;

private:
    /// What one range of features lists, kept from listing to listing.
    struct ChunkPairs
    {
        std::vector<SheetEdgePair> edgePairs;
        std::vector<SheetTrianglePair> cornerPairs;
        std::vector<std::size_t> patches; ///< the patches one query met
        std::vector<Index> found;         ///< their triangles whose boxes meet the query's, increasing
        std::vector<Index> edges;         ///< those triangles' edges, each once
    };

    /// The obstacles' features in the world at `time`, moving with their mean motion until time + dt.
    void placeFeatures(Real time, Real dt, EdgeContactCandidates& out);
    /// The gap between the box of the surface's masses, each grown by its reach and the radius, and the nearest
    /// feature's box over the span (0 if they meet).
    Real clearance(const std::vector<Vec3>& x, const std::vector<Real>& reach, Real radius, Real span,
                   const EdgeContactCandidates& out);
    /// The patches' boxes, then the tree's (built the first time); throws NumericalError for a box beyond what
    /// Bullet's tree can hold (a sheet that diverged).
    void refit(const std::vector<Vec3>& x, const std::vector<Real>& reach, Real radius, Real time);
    [[noreturn]] void throwDiverged(const std::vector<Vec3>& x, const std::vector<Real>& reach, std::size_t patch,
                                    Real time) const;
    void build();
    /// A triangle's box grown by its masses' largest reach and the radius.
    void triangleBox(const std::vector<Vec3>& x, const std::vector<Real>& reach, Real radius, Index triangle, Vec3& low,
                     Vec3& high) const;
    /// Fills chunk.found with the triangles whose boxes meet the box [low, high].
    void trianglesMeeting(const std::vector<Vec3>& x, const std::vector<Real>& reach, Real radius, const Vec3& low,
                          const Vec3& high, ChunkPairs& chunk) const;
    /// Appends the pairs of obstacle edge f (corner c) that may meet the sheet within the span.
    void listEdge(const std::vector<Vec3>& x, const std::vector<Real>& reach, Real radius, Real span,
                  const EdgeContactCandidates& out, Index f, ChunkPairs& chunk) const;
    void listCorner(const std::vector<Vec3>& x, const std::vector<Real>& reach, Real radius, Real span,
                    const EdgeContactCandidates& out, Index c, ChunkPairs& chunk) const;

    const BulletEnvironment& m_environment;
    std::vector<SharpFeatures> m_features; ///< per obstacle, in its own frame (empty for the room's walls)
    std::unique_ptr<btDbvt> m_tree;
    SheetSurface m_surface;
    std::vector<btDbvtNode*> m_leaves;         ///< per patch of the surface
    std::vector<btDbvtNode*> m_internalNodes;  ///< children before their parent
    std::vector<Vec3> m_low, m_high;           ///< per patch, its box grown by its masses' reach and the radius
    PerChunk<ChunkPairs> m_chunks;             ///< per range of features
    std::vector<Vec3> m_chunkLow, m_chunkHigh; ///< per range of surface masses, their box
};
} // namespace masse::bridge
