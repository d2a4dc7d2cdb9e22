#pragma once
/// What the sheet's edge contact (EdgeContact.h) asks of the obstacles: their sharp edges and corners near the sheet's
/// surface, and which sheet edges and triangles may meet them during a frame. The Bullet bridge implements it (a btDbvt
/// over the sheet's surface triangles, queried by every sharp feature of every obstacle); the core sees only this.

#include "core/Types.h"
#include "core/lattice/LatticeSurface.h"

#include <cstdint>
#include <limits>
#include <vector>

namespace masse
{
/// An edge of an obstacle where two of its faces meet at a convex angle (a ridge the sheet can fold over), in the
/// world where it is when the candidates are listed.
struct ObstacleEdge
{
    Vec3 start = Vec3::Zero();
    Vec3 end = Vec3::Zero();
    Vec3 startVelocity = Vec3::Zero(); ///< m/s, the obstacle's mean motion over the frame at each end
    Vec3 endVelocity = Vec3::Zero();
    /// The outward normals of the two faces that meet at the edge: a point near the edge is outside the obstacle when
    /// it lies in front of either face. (An open mesh's rim has one face: the second normal is the first reversed, so
    /// every point counts as outside.)
    Vec3 normals[2] = {Vec3::UnitY(), Vec3::UnitY()};
    int obstacle = -1;
};

/// A corner of an obstacle where at least one of its sharp edges ends (a prism's apex, a box's corner).
struct ObstacleCorner
{
    Vec3 point = Vec3::Zero();
    Vec3 velocity = Vec3::Zero();
    /// Its faces' outward normals, EdgeContactCandidates::cornerNormals[firstNormal, firstNormal + normalCount): a
    /// point near the corner is outside the obstacle when it lies in front of any of them.
    std::uint32_t firstNormal = 0;
    std::uint32_t normalCount = 0;
    int obstacle = -1;
};

/// A sheet edge (into SheetSurface::edges) and an obstacle edge that may meet.
struct SheetEdgePair
{
    Index sheetEdge = 0;
    Index obstacleEdge = 0;
};

/// A sheet triangle (into SheetSurface::triangles) and an obstacle corner that may meet.
struct SheetTrianglePair
{
    Index triangle = 0;
    Index corner = 0;
};

struct EdgeContactCandidates
{
    std::vector<ObstacleEdge> edges;
    std::vector<ObstacleCorner> corners;
    std::vector<Vec3> cornerNormals;
    std::vector<SheetEdgePair> edgePairs;       ///< by obstacle edge, then sheet edge, increasing
    std::vector<SheetTrianglePair> cornerPairs; ///< by corner, then triangle, increasing
    /// m, how far apart the surface, every mass grown by its reach and the radius, and the features, each moved as far
    /// as it will in the frame, at least are (boxes around each; 0 when they meet, infinite without features).
    Real clearance = std::numeric_limits<Real>::infinity();
};

class EdgeContactDetector
{
public:
    virtual ~EdgeContactDetector() = default;
    /// The sheet's surface, once (its topology never changes).
    virtual void setSurface(const SheetSurface& surface) = 0;
    /// Replaces `out` by the obstacles' sharp edges and corners where they are at `time`, moving as they will until
    /// `time + dt`, and every pair of a sheet edge and an obstacle edge, and of a sheet triangle and an obstacle
    /// corner, that may come within `radius` of each other by then while each surface mass i stays within reach[i] of
    /// x[i]. The lists are the same whatever the thread count.
    virtual void findCandidates(const std::vector<Vec3>& x, const std::vector<Real>& reach, Real radius, Real time,
                                Real dt, EdgeContactCandidates& out) = 0;
};
} // namespace masse
