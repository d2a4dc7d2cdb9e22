#pragma once
/// The shape of an obstacle: its Bullet collision shape, and its own faces (for contact reports and drawing).
///
/// A convex solid (a polyhedron or a hull) becomes a btConvexHullShape with zero margin, so contact is with the exact
/// polyhedron, not a rounded one; its faces are polygons with outward normals. A mesh becomes a
/// btBvhTriangleMeshShape whose triangles remember which face they came from.
///
/// Face order: a polyhedron's and a mesh's as their polygons are given (each scene shape numbers its own faces, in its
/// file under src/scene/shapes/, and data/scenes/README.md lists them); a hull's as Bullet's convex-hull computer
/// finds them.

#include "ObstacleShape.h"

#include <array>
#include <memory>
#include <vector>

class btCollisionShape;
class btTriangleMesh;

namespace masse::bridge
{
struct Face
{
    std::vector<int> vertices; ///< indices into ObstacleGeometry::vertices, counter-clockwise seen from outside
    Vec3 normal;               ///< outward, local frame
    Real offset;               ///< normal . x on the face's plane
};

struct ObstacleGeometry
{
    ObstacleGeometry();
    ~ObstacleGeometry();
    ObstacleGeometry(ObstacleGeometry&&) noexcept;
    ObstacleGeometry& operator=(ObstacleGeometry&&) noexcept;

    bool convex = true;
    std::vector<Vec3> vertices; ///< local frame
    std::vector<Face> faces;
    std::vector<int> triangleFace; ///< mesh only: the face of each Bullet triangle
    /// mesh only: each Bullet triangle's own unit normal, (b - a) x (c - a) of its triangleCorners normalised (zero if
    /// degenerate); contact detection takes it for a centre on the triangle, with those bits
    std::vector<Vec3> triangleNormals;
    /// mesh only: each Bullet triangle's corners, read back through btScalar as a triangle walk hands them over (the
    /// same bits whatever Bullet's precision)
    std::vector<std::array<Vec3, 3>> triangleCorners;
    Vec3 localMin = Vec3::Zero();
    Vec3 localMax = Vec3::Zero();
    std::unique_ptr<btTriangleMesh> triangles;
    std::unique_ptr<btCollisionShape> shape;

    /// The face a contact at local point p with local normal n (from the obstacle outward) lies on: among faces whose
    /// plane passes through p, the one whose normal is closest to n.
    int faceAt(const Vec3& localPoint, const Vec3& localNormal) const;
};

/// Builds the geometry of a solid; throws InputError for a degenerate hull (fewer than 4 points not all in one plane),
/// or a polyhedron or mesh without faces or with a face that names a vertex it does not have (naming "polyhedron" or
/// "mesh").
ObstacleGeometry makeObstacleGeometry(const ObstacleShape& shape);
} // namespace masse::bridge
