#pragma once
/// The nearest points of eight triangles of a mesh obstacle to one sphere's centre at once, on the AVX-512 path (the
/// AVX2 one takes them four at a time): the box and plane tests that turn a far triangle away, then
/// closestPointOnTriangle (ClosestPointOnTriangle.h) on the triangles they let through. A mass whose triangles are kept
/// from the frame before (NearbyTriangles.h) tests some ten of them a query, most of which pass both tests, so the
/// nearest point, one triangle at a time, is most of a forming scene's contact detection.
///
/// Each lane does the scalar code's IEEE operations in its order, with its branches as masks (the Voronoi regions
/// tested in the scalar code's order, the first that holds taking the lane), so each lane's nearest point has the bits
/// of the scalar code's, and the same triangles are turned away.

#include "core/Types.h"

#include <array>
#include <cstdint>
#include <vector>

namespace masse::bridge
{
struct NearestOnTrianglesOfEight
{
    /// Bit l set: lane l's triangle passed the box and plane tests and is not degenerate, and its nearest point is
    /// below.
    std::uint8_t near = 0;
    /// Bit l set: lane l's triangle passed the tests but is degenerate (the scalar code's last case, its corners
    /// collinear to rounding); its point is not computed here.
    std::uint8_t degenerate = 0;
    alignas(64) Real nearestX[8];
    alignas(64) Real nearestY[8];
    alignas(64) Real nearestZ[8];
    /// The distance from the centre to the nearest point, (centre - nearest).norm(), and that offset over it (its
    /// direction, not finite where the distance is 0): the scalar code's bits, computed for the eight because most
    /// triangles that pass the tests lie within the search and need both.
    alignas(64) Real gap[8];
    alignas(64) Real directionX[8];
    alignas(64) Real directionY[8];
    alignas(64) Real directionZ[8];
};

/// Whether nearestOnTrianglesOfEight runs here: the AVX2 or the AVX-512 path is active (SimdPath.h) and the build has
/// the kernel.
bool nearestOnTrianglesOfEightAvailable();

/// For the triangles triangles[0..count) (count from 1 to 8) of a mesh with the given corners and unit normals (mesh
/// frame), against `centre` (mesh frame): those farther than `rejectBeyond` by their box or their plane are turned
/// away, and the others' nearest points found, as the scalar test does. Requires nearestOnTrianglesOfEightAvailable().
void nearestOnTrianglesOfEight(const std::vector<std::array<Vec3, 3>>& corners, const std::vector<Vec3>& normals,
                               const std::int32_t* triangles, int count, const Vec3& centre, Real rejectBeyond,
                               NearestOnTrianglesOfEight& out);
} // namespace masse::bridge
