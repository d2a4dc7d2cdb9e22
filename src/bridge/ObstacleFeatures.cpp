#include "ObstacleFeatures.h"

#include <algorithm>
#include <array>
#include <cstdint>

namespace masse::bridge
{
namespace
{
/// One side of an edge as a face's boundary gives it: the edge's vertices (lower index first) and the face.
struct FaceSide
{
    int low = 0;
    int high = 0;
    int face = 0;
    bool operator<(const FaceSide& other) const
    {
        return std::array<int, 3>{low, high, face} < std::array<int, 3>{other.low, other.high, other.face};
    }
};

Vec3 faceCentre(const ObstacleGeometry& g, const Face& face)
{
    Vec3 sum = Vec3::Zero();
    for (const int v : face.vertices)
    {
        sum += g.vertices[std::size_t(v)];
    }
    return sum / Real(face.vertices.size());
}
} // namespace

SharpFeatures sharpFeatures(const ObstacleGeometry& g)
{
    std::vector<FaceSide> sides;
    for (std::size_t f = 0; f < g.faces.size(); ++f)
    {
        const std::vector<int>& loop = g.faces[f].vertices;
        for (std::size_t k = 0; k < loop.size(); ++k)
        {
            const int a = loop[k];
            const int b = loop[(k + 1) % loop.size()];
            if (a != b)
            {
                sides.push_back({std::min(a, b), std::max(a, b), int(f)});
            }
        }
    }
    std::sort(sides.begin(), sides.end());
    // Tolerances relative to the obstacle's size: a crease this shallow is flat to rounding.
    const Real size = std::max((g.localMax - g.localMin).norm(), Real(1e-9));
    SharpFeatures features;
    std::vector<std::uint8_t> onSharpEdge(g.vertices.size(), 0);
    std::vector<std::uint8_t> onRim(g.vertices.size(), 0);
    for (std::size_t k = 0; k < sides.size();)
    {
        std::size_t next = k + 1;
        while (next < sides.size() && sides[next].low == sides[k].low && sides[next].high == sides[k].high)
        {
            ++next;
        }
        SharpEdge edge;
        edge.start = sides[k].low;
        edge.end = sides[k].high;
        const Face& first = g.faces[std::size_t(sides[k].face)];
        bool sharp = false;
        if (next - k == 1)
        {
            edge.normals[0] = first.normal;
            edge.normals[1] = -first.normal;
            sharp = true;
            onRim[std::size_t(edge.start)] = 1;
            onRim[std::size_t(edge.end)] = 1;
        }
        else if (next - k == 2)
        {
            const Face& second = g.faces[std::size_t(sides[k + 1].face)];
            // Convex: the second face lies behind the first's plane; flat faces (a mesh's triangles of one face)
            // are not an edge at all.
            const Real behind = first.normal.dot(faceCentre(g, second)) - first.offset;
            sharp = first.normal.dot(second.normal) < 1 - 1e-9 && behind < -1e-9 * size;
            edge.normals[0] = first.normal;
            edge.normals[1] = second.normal;
        }
        // (An edge of three faces or more, a mesh's non-manifold seam, has no outside to tell: left out.)
        if (sharp)
        {
            features.edges.push_back(edge);
            onSharpEdge[std::size_t(edge.start)] = 1;
            onSharpEdge[std::size_t(edge.end)] = 1;
        }
        k = next;
    }
    for (std::size_t v = 0; v < g.vertices.size(); ++v)
    {
        if (!onSharpEdge[v])
        {
            continue;
        }
        SharpCorner corner;
        corner.vertex = int(v);
        corner.firstNormal = features.cornerNormals.size();
        for (const Face& face : g.faces)
        {
            if (std::find(face.vertices.begin(), face.vertices.end(), int(v)) != face.vertices.end())
            {
                features.cornerNormals.push_back(face.normal);
            }
        }
        if (onRim[v] && corner.firstNormal < features.cornerNormals.size())
        {
            // A corner of an open mesh's rim has no inside either (ObstacleEdge's rim).
            features.cornerNormals.push_back(-features.cornerNormals[corner.firstNormal]);
        }
        corner.normalCount = features.cornerNormals.size() - corner.firstNormal;
        features.corners.push_back(corner);
    }
    return features;
}
} // namespace masse::bridge
