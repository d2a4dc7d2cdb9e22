#include "FacePlaneDistance.h"

namespace masse::bridge
{
std::optional<FacePlaneDistance> facePlaneDistance(const ObstacleGeometry& g, const Vec3& localPoint)
{
    if (!g.convex || g.faces.empty())
    {
        return std::nullopt;
    }
    std::size_t nearest = 0;
    Real height = g.faces[0].normal.dot(localPoint) - g.faces[0].offset;
    for (std::size_t f = 1; f < g.faces.size(); ++f)
    {
        const Real h = g.faces[f].normal.dot(localPoint) - g.faces[f].offset;
        if (h > height)
        {
            height = h;
            nearest = f;
        }
    }
    const Face& face = g.faces[nearest];
    const Vec3 projection = localPoint - height * face.normal;
    if (height > 0)
    {
        // In front of the face: the projection must lie behind (or on) every other face's plane. Strictly so up to
        // rounding; a projection on an edge is left to nearestOnFrontFaces, which handles edges exactly.
        for (std::size_t f = 0; f < g.faces.size(); ++f)
        {
            if (f != nearest && g.faces[f].normal.dot(projection) - g.faces[f].offset >= 0)
            {
                return std::nullopt;
            }
        }
    }
    return FacePlaneDistance{height, int(nearest), projection};
}
} // namespace masse::bridge
