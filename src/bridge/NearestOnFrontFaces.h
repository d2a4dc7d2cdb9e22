#pragma once
/// The nearest surface point of a convex polyhedron to a point outside it, in closed form: what FacePlaneDistance
/// leaves (the nearest point on an edge or a vertex, or on a face other than the one the point is farthest in front
/// of), instead of Bullet's GJK. GJK is an iterative search for a shape whose nearest point has a closed form
/// here: on a sheet sagging between two boxes (the contact bench, 256x2x256) some 10,000 masses a frame are near a
/// box's edge, and GJK would take over half of the contact detection's time.
///
/// For a point p outside, the nearest point q of the polyhedron lies on a face whose plane p is in front of: p - q lies
/// in the cone of the outward normals of the faces through q, so (p - q) . n > 0 for one of them, and that face's
/// plane passes through q. So q is the nearest of the nearest points of those front faces; each face is a convex
/// polygon, taken as a fan of triangles whose nearest points have a closed form (ClosestPointOnTriangle.h).

#include "ObstacleGeometry.h"

namespace masse::bridge
{
struct NearestOnFrontFaces
{
    Real distance; ///< from the point to the surface, >= 0
    Vec3 point;    ///< the nearest surface point, in the polyhedron's frame
    /// From that point towards the point asked about, unit length, in the polyhedron's frame (for a point on the
    /// surface to the bit, the normal of the face it is farthest in front of).
    Vec3 normal;
};

/// The nearest surface point of convex geometry g to localPoint (both in g's frame), which lies in front of at least
/// one face's plane.
NearestOnFrontFaces nearestOnFrontFaces(const ObstacleGeometry& g, const Vec3& localPoint);
} // namespace masse::bridge
