#include "NearestOnFrontFaces.h"

#include "core/contact/ClosestPointOnTriangle.h"

#include <cmath>
#include <limits>

namespace masse::bridge
{
NearestOnFrontFaces nearestOnFrontFaces(const ObstacleGeometry& g, const Vec3& localPoint)
{
    Real nearestSquared = std::numeric_limits<Real>::infinity();
    Vec3 nearest = localPoint;
    Real greatestHeight = 0;
    Vec3 frontNormal = Vec3::Zero(); // of the face the point is farthest in front of
    for (const Face& face : g.faces)
    {
        const Real height = face.normal.dot(localPoint) - face.offset;
        if (!(height > 0))
        {
            continue;
        }
        if (height > greatestHeight)
        {
            greatestHeight = height;
            frontNormal = face.normal;
        }
        const Vec3& first = g.vertices[std::size_t(face.vertices[0])];
        for (std::size_t k = 1; k + 1 < face.vertices.size(); ++k)
        {
            const Vec3 candidate = closestPointOnTriangle(localPoint, first, g.vertices[std::size_t(face.vertices[k])],
                                                          g.vertices[std::size_t(face.vertices[k + 1])]);
            const Real squared = (localPoint - candidate).squaredNorm();
            if (squared < nearestSquared)
            {
                nearestSquared = squared;
                nearest = candidate;
            }
        }
    }
    const Real distance = std::sqrt(nearestSquared);
    if (!(distance > 0))
    {
        // In front of a plane by a rounding error and on the surface to the bit: no direction to the point, so the
        // normal of the face it is in front of stands in (as the face's normal does for a mesh's triangle).
        return {0, nearest, frontNormal};
    }
    return {distance, nearest, (localPoint - nearest) / distance};
}
} // namespace masse::bridge
