#pragma once
/// The nearest point of a triangle to a point, in closed form.
///
/// A mesh obstacle's triangles were met by GJK one at a time, an iterative search on a shape whose nearest point has
/// a closed form: over half of a 64x2x64 vacuum-forming run (the sheet lying on the cup mould's triangles) went to
/// GJK and its support functions. The closed form below is Ericson's (Real-Time Collision Detection, 5.1.5): find the
/// Voronoi region of the triangle (a vertex, an edge or the face) the point lies in from signed barycentric terms,
/// then project onto that feature. It is exact up to rounding, where GJK stops at its own tolerance.

#include "core/Types.h"

namespace masse::bridge
{
/// The point of triangle (a, b, c) nearest to p. The triangle may be degenerate (its nearest edge or vertex answers).
Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);
} // namespace masse::bridge
