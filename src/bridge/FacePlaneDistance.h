#pragma once
/// The nearest point of a convex polyhedron's surface to a point, from its face planes alone, where that is exact.
///
/// A convex polyhedron is the intersection of its faces' half-spaces. For a point inside, the nearest surface point
/// is its projection onto the nearest face plane. For a point outside, let f be the face whose plane it is farthest
/// in front of: if its projection onto f's plane lies behind every other plane, the projection is on the polyhedron
/// and no point of the polyhedron is nearer (every one lies behind f's plane). Both cases cover a sheet lying on or
/// pressed into a face, which is most of contact; what is left (nearest to an edge or a vertex) goes to
/// NearestOnFrontFaces.h. This is what Bullet itself does for a sphere against a box (btSphereBoxCollisionAlgorithm),
/// for any convex polyhedron.

#include "ObstacleGeometry.h"

#include <optional>

namespace masse::bridge
{
struct FacePlaneDistance
{
    Real distance; ///< from the point to the surface, negative inside
    int face;      ///< the face the nearest point lies on
    Vec3 point;    ///< the nearest surface point, in the polyhedron's frame
};

/// The nearest surface point of convex geometry g to localPoint (both in g's frame) when a face plane gives it
/// exactly; nullopt when the nearest point is on an edge or a vertex (or g is not convex).
std::optional<FacePlaneDistance> facePlaneDistance(const ObstacleGeometry& g, const Vec3& localPoint);
} // namespace masse::bridge
