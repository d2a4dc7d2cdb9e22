#pragma once
/// The point of a triangle closest to a point, as barycentric weights (Ericson, Real-Time Collision Detection, 5.1.5):
/// the narrowphase of the sheet's self-contact and of a mesh obstacle's triangles against each mass (rather than GJK,
/// an iterative search on a shape whose nearest point has a closed form: GJK on the mould's triangles takes over half
/// of a 64x2x64 vacuum-forming run). The Voronoi region of the triangle (a vertex, an edge or the face) the point lies
/// in is found from signed dot products, then the point is projected onto that feature.

#include "core/Types.h"

namespace masse
{
/// Weights (wa, wb, wc), summing to 1 and each >= 0, of the point of triangle abc closest to p.
inline Vec3 closestPointWeights(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c)
{
    const Vec3 ab = b - a;
    const Vec3 ac = c - a;
    const Vec3 ap = p - a;
    const Real d1 = ab.dot(ap);
    const Real d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0)
    {
        return Vec3(1, 0, 0);
    }
    const Vec3 bp = p - b;
    const Real d3 = ab.dot(bp);
    const Real d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3)
    {
        return Vec3(0, 1, 0);
    }
    const Real vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0)
    {
        const Real v = d1 / (d1 - d3);
        return Vec3(1 - v, v, 0);
    }
    const Vec3 cp = p - c;
    const Real d5 = ab.dot(cp);
    const Real d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6)
    {
        return Vec3(0, 0, 1);
    }
    const Real vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0)
    {
        const Real w = d2 / (d2 - d6);
        return Vec3(1 - w, 0, w);
    }
    const Real va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    {
        const Real w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
        return Vec3(0, 1 - w, w);
    }
    const Real sum = va + vb + vc;
    if (!(sum > 0)) // a degenerate (collinear) triangle whose tests above all failed by rounding: its nearest corner
    {
        const Real da = ap.squaredNorm();
        const Real db = bp.squaredNorm();
        const Real dc = cp.squaredNorm();
        return da <= db && da <= dc ? Vec3(1, 0, 0) : (db <= dc ? Vec3(0, 1, 0) : Vec3(0, 0, 1));
    }
    const Real denominator = Real(1) / sum;
    const Real v = vb * denominator;
    const Real w = vc * denominator;
    return Vec3(1 - v - w, v, w);
}

/// The point of triangle abc closest to p.
inline Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c)
{
    const Vec3 w = closestPointWeights(p, a, b, c);
    return w.x() * a + w.y() * b + w.z() * c;
}
} // namespace masse
