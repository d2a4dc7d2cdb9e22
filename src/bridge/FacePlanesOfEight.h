#pragma once
/// facePlaneDistance (FacePlaneDistance.h) for eight points at once on the AVX-512 path, carried on to the contact
/// plane closestFeatures builds from it: the world-frame normal of the nearest face, the nearest surface point and the
/// plane's offset. Detection asks this of nearly every mass of a sheet lying on a box each frame; one at a time it is
/// most of detection's time (a quaternion rotation in, one dot product per face twice over, two rotations out).
///
/// Each lane does the scalar code's IEEE operations in its order (Eigen's quaternion rotation, its dot products,
/// face by face, with the branches as masks), so each lane's values have the bits the scalar query gives.

#include "KinematicPath.h"
#include "ObstacleGeometry.h"

#include <cstdint>

namespace masse::bridge
{
struct FacePlanesOfEight
{
    /// Bit l set: a face plane gives lane l's nearest point, and the fields below hold it. Clear: the nearest point is
    /// on an edge or a vertex, the scalar query's nearestOnFrontFaces case, and the fields are meaningless.
    std::uint8_t found = 0;
    alignas(64) Real distance[8]; ///< from the centre to the surface, negative inside
    alignas(64) Real normalX[8];  ///< the face's outward normal, world frame
    alignas(64) Real normalY[8];
    alignas(64) Real normalZ[8];
    alignas(64) Real pointX[8]; ///< the nearest surface point, world frame
    alignas(64) Real pointY[8];
    alignas(64) Real pointZ[8];
    alignas(64) Real offset[8]; ///< normal . point
    alignas(64) std::int64_t face[8];
};

/// Whether facePlanesOfEight runs here: the AVX-512 path is active (SimdPath.h) and the build has the kernel.
bool facePlanesOfEightAvailable();

/// The face planes of convex geometry g (posed at `pose`) nearest to centres[0..8). Requires g convex with faces
/// and facePlanesOfEightAvailable().
void facePlanesOfEight(const ObstacleGeometry& g, const Pose& pose, const Vec3* centres, FacePlanesOfEight& out);
} // namespace masse::bridge
