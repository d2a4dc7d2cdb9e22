#include "NearestOnFrontFaces.h"

#include "core/ClosestPointOnTriangle.h"

#include <cmath>
#include <limits>

namespace masse::bridge
{
NearestOnFrontFaces nearestOnFrontFaces(const ObstacleGeometry& g, const Vec3& localPoint)
{
    Real nearestSquared = std::numeric_limits<Real>::infinity();
    Vec3 nearest = localPoint;
    for (const Face& face : g.faces)
    {
        if (!(face.normal.dot(localPoint) - face.offset > 0))
        {
            continue;
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
    return {distance, nearest, (localPoint - nearest) / distance};
}
} // namespace masse::bridge
