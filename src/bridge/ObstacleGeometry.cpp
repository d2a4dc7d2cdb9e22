#include "ObstacleGeometry.h"

#include "BulletMath.h"

#include "core/InputError.h"

#include <BulletCollision/CollisionShapes/btBvhTriangleMeshShape.h>
#include <BulletCollision/CollisionShapes/btConvexHullShape.h>
#include <BulletCollision/CollisionShapes/btTriangleMesh.h>
#include <LinearMath/btConvexHullComputer.h>

#include <algorithm>
#include <cmath>
#include <limits>

namespace masse::bridge
{
ObstacleGeometry::ObstacleGeometry() = default;
ObstacleGeometry::~ObstacleGeometry() = default;
ObstacleGeometry::ObstacleGeometry(ObstacleGeometry&&) noexcept = default;
ObstacleGeometry& ObstacleGeometry::operator=(ObstacleGeometry&&) noexcept = default;

namespace
{
/// Outward normal and plane offset of a polygon (Newell's method, robust for any planar polygon).
void finishFace(const std::vector<Vec3>& vertices, const Vec3& interior, Face& face)
{
    Vec3 normal = Vec3::Zero();
    Vec3 centre = Vec3::Zero();
    const std::size_t n = face.vertices.size();
    for (std::size_t k = 0; k < n; ++k)
    {
        const Vec3& a = vertices[std::size_t(face.vertices[k])];
        const Vec3& b = vertices[std::size_t(face.vertices[(k + 1) % n])];
        normal += Vec3((a.y() - b.y()) * (a.z() + b.z()), (a.z() - b.z()) * (a.x() + b.x()),
                       (a.x() - b.x()) * (a.y() + b.y()));
        centre += a / Real(n);
    }
    normal.normalize();
    if (normal.dot(centre - interior) < 0)
    {
        normal = -normal;
        std::reverse(face.vertices.begin(), face.vertices.end());
    }
    face.normal = normal;
    face.offset = normal.dot(centre);
}

void addFace(ObstacleGeometry& g, std::vector<int> vertices, const Vec3& interior)
{
    Face face;
    face.vertices = std::move(vertices);
    finishFace(g.vertices, interior, face);
    g.faces.push_back(std::move(face));
}

Vec3 centroid(const std::vector<Vec3>& points)
{
    Vec3 sum = Vec3::Zero();
    for (const Vec3& p : points)
    {
        sum += p;
    }
    return sum / Real(points.size());
}

/// Throws unless the points span three dimensions.
void requireSolid(const std::vector<Vec3>& points)
{
    const std::string message =
        "a hull needs at least 4 points not all in one plane (got " + std::to_string(points.size()) + " points";
    if (points.size() < 4)
    {
        throw InputError(message + ")");
    }
    Real scale = 0;
    for (const Vec3& p : points)
    {
        if (!p.allFinite())
        {
            throw InputError("hullPoints", "must be finite numbers");
        }
        scale = std::max(scale, (p - points[0]).norm());
    }
    const Real tolerance = 1e-9 * std::max(scale, Real(1e-12));
    // Farthest point from the first, then from the line through both, then from the plane through all three.
    std::size_t b = 0;
    for (std::size_t i = 1; i < points.size(); ++i)
    {
        b = (points[i] - points[0]).norm() > (points[b] - points[0]).norm() ? i : b;
    }
    const Vec3 axis = (points[b] - points[0]).normalized();
    std::size_t c = 0;
    Real farthest = 0;
    for (std::size_t i = 0; i < points.size(); ++i)
    {
        const Real d = (points[i] - points[0]).cross(axis).norm();
        if (d > farthest)
        {
            farthest = d;
            c = i;
        }
    }
    if (scale <= tolerance || farthest <= tolerance)
    {
        throw InputError(message + ", all on one line)");
    }
    const Vec3 normal = axis.cross(points[c] - points[0]).normalized();
    Real height = 0;
    for (const Vec3& p : points)
    {
        height = std::max(height, std::abs((p - points[0]).dot(normal)));
    }
    if (height <= tolerance)
    {
        throw InputError(message + ", all in one plane)");
    }
}

void makeHull(const ObstacleShape& shape, ObstacleGeometry& g)
{
    requireSolid(shape.hullPoints);
    std::vector<btVector3> points;
    for (const Vec3& p : shape.hullPoints)
    {
        points.push_back(toBullet(p));
    }
    btConvexHullComputer hull;
    hull.compute(&points[0].x(), int(sizeof(btVector3)), int(points.size()), 0, 0);
    for (int i = 0; i < hull.vertices.size(); ++i)
    {
        g.vertices.push_back(toVec3(hull.vertices[i]));
    }
    const Vec3 inside = centroid(g.vertices);
    for (int f = 0; f < hull.faces.size(); ++f)
    {
        const btConvexHullComputer::Edge* first = &hull.edges[hull.faces[f]];
        const btConvexHullComputer::Edge* edge = first;
        std::vector<int> loop;
        do
        {
            loop.push_back(edge->getSourceVertex());
            edge = edge->getNextEdgeOfFace();
        } while (edge != first);
        addFace(g, std::move(loop), inside);
    }
}

/// Throws InputError naming `field` unless every face has three vertices or more, all of them the mesh's and finite,
/// and Bullet can index every triangle. A mesh read from a file has passed these checks already (MeshFile.h); one
/// built in code may not have.
void requirePolygons(const PolygonMesh& mesh, const char* field)
{
    if (mesh.faces.empty())
    {
        throw InputError(field, "has no faces");
    }
    std::size_t triangles = 0;
    for (const std::vector<int>& face : mesh.faces)
    {
        if (face.size() < 3)
        {
            throw InputError(field, "a face has fewer than three vertices");
        }
        triangles += face.size() - 2;
        for (int v : face)
        {
            if (v < 0 || std::size_t(v) >= mesh.vertices.size())
            {
                throw InputError(field, "a face names vertex " + std::to_string(v) + " of " +
                                            std::to_string(mesh.vertices.size()));
            }
        }
    }
    if (triangles > maxMeshTriangles)
    {
        throw InputError(field, "has " + std::to_string(triangles) + " triangles, more than Bullet's " +
                                    std::to_string(maxMeshTriangles));
    }
    for (const Vec3& v : mesh.vertices)
    {
        if (!v.allFinite())
        {
            throw InputError(field, "a vertex is not a finite number");
        }
    }
}

void makePolyhedron(const ObstacleShape& shape, ObstacleGeometry& g)
{
    requirePolygons(shape.polygons, "polyhedron");
    g.vertices = shape.polygons.vertices;
    const Vec3 inside = centroid(g.vertices);
    for (const std::vector<int>& face : shape.polygons.faces)
    {
        addFace(g, face, inside);
    }
}

void makeMesh(const ObstacleShape& shape, ObstacleGeometry& g)
{
    const PolygonMesh& mesh = shape.polygons;
    requirePolygons(mesh, "mesh");
    g.vertices = mesh.vertices;
    g.convex = false;
    g.triangles = std::make_unique<btTriangleMesh>(true, false);
    for (std::size_t f = 0; f < mesh.faces.size(); ++f)
    {
        Face face;
        face.vertices = mesh.faces[f];
        // A mesh has no inside: keep the file's winding and take its normal as outward.
        Vec3 normal = Vec3::Zero();
        const std::size_t n = face.vertices.size();
        for (std::size_t k = 0; k < n; ++k)
        {
            const Vec3& a = g.vertices[std::size_t(face.vertices[k])];
            const Vec3& b = g.vertices[std::size_t(face.vertices[(k + 1) % n])];
            normal +=
                (a - g.vertices[std::size_t(face.vertices[0])]).cross(b - g.vertices[std::size_t(face.vertices[0])]);
        }
        face.normal = normal.norm() > 0 ? normal.normalized() : Vec3::UnitY();
        face.offset = face.normal.dot(g.vertices[std::size_t(face.vertices[0])]);
        for (std::size_t k = 1; k + 1 < n; ++k) // fan triangulation for Bullet
        {
            const Vec3& a = g.vertices[std::size_t(face.vertices[0])];
            const Vec3& b = g.vertices[std::size_t(face.vertices[k])];
            const Vec3& c = g.vertices[std::size_t(face.vertices[k + 1])];
            g.triangles->addTriangle(toBullet(a), toBullet(b), toBullet(c));
            g.triangleFace.push_back(int(f));
            g.triangleCorners.push_back({toVec3(toBullet(a)), toVec3(toBullet(b)), toVec3(toBullet(c))});
            const std::array<Vec3, 3>& corners = g.triangleCorners.back();
            const Vec3 cross = (corners[1] - corners[0]).cross(corners[2] - corners[0]);
            g.triangleNormals.push_back(cross.norm() > 0 ? Vec3(cross.normalized()) : Vec3::Zero());
        }
        g.faces.push_back(std::move(face));
    }
    auto bvh = std::make_unique<btBvhTriangleMeshShape>(g.triangles.get(), true);
    bvh->setMargin(0);
    g.shape = std::move(bvh);
}
} // namespace

int ObstacleGeometry::faceAt(const Vec3& localPoint, const Vec3& localNormal) const
{
    const Real tolerance = 1e-6 * std::max(Real(1e-3), (localMax - localMin).norm());
    int best = -1;
    Real bestAlignment = -std::numeric_limits<Real>::infinity();
    int fallback = -1;
    Real fallbackAlignment = -std::numeric_limits<Real>::infinity();
    for (std::size_t f = 0; f < faces.size(); ++f)
    {
        const Real alignment = faces[f].normal.dot(localNormal);
        if (alignment > fallbackAlignment)
        {
            fallbackAlignment = alignment;
            fallback = int(f);
        }
        if (std::abs(faces[f].normal.dot(localPoint) - faces[f].offset) <= tolerance && alignment > bestAlignment)
        {
            bestAlignment = alignment;
            best = int(f);
        }
    }
    return best >= 0 ? best : fallback;
}

ObstacleGeometry makeObstacleGeometry(const ObstacleShape& shape)
{
    ObstacleGeometry g;
    switch (shape.kind)
    {
    case SolidKind::Polyhedron:
        makePolyhedron(shape, g);
        break;
    case SolidKind::Hull:
        makeHull(shape, g);
        break;
    case SolidKind::Mesh:
        makeMesh(shape, g);
        break;
    }
    g.localMin = g.vertices.front();
    g.localMax = g.vertices.front();
    for (const Vec3& v : g.vertices)
    {
        g.localMin = g.localMin.cwiseMin(v);
        g.localMax = g.localMax.cwiseMax(v);
    }
    if (g.convex)
    {
        auto hull = std::make_unique<btConvexHullShape>();
        for (const Vec3& v : g.vertices)
        {
            hull->addPoint(toBullet(v), false);
        }
        hull->recalcLocalAabb();
        hull->setMargin(0); // the exact polyhedron, not one rounded by Bullet's default 4 cm margin
        g.shape = std::move(hull);
    }
    return g;
}
} // namespace masse::bridge
