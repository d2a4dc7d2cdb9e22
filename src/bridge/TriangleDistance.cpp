#include "TriangleDistance.h"

namespace masse::bridge
{
Vec3 closestPointOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c)
{
    // Each test below asks whether p lies in one feature's Voronoi region, in the order vertex a, vertex b, edge ab,
    // vertex c, edge ac, edge bc, face; the d terms are dot products of the edges with p's offsets from the vertices.
    const Vec3 ab = b - a;
    const Vec3 ac = c - a;
    const Vec3 ap = p - a;
    const Real d1 = ab.dot(ap);
    const Real d2 = ac.dot(ap);
    if (d1 <= 0 && d2 <= 0)
    {
        return a;
    }
    const Vec3 bp = p - b;
    const Real d3 = ab.dot(bp);
    const Real d4 = ac.dot(bp);
    if (d3 >= 0 && d4 <= d3)
    {
        return b;
    }
    const Real vc = d1 * d4 - d3 * d2;
    if (vc <= 0 && d1 >= 0 && d3 <= 0)
    {
        return a + (d1 / (d1 - d3)) * ab;
    }
    const Vec3 cp = p - c;
    const Real d5 = ab.dot(cp);
    const Real d6 = ac.dot(cp);
    if (d6 >= 0 && d5 <= d6)
    {
        return c;
    }
    const Real vb = d5 * d2 - d1 * d6;
    if (vb <= 0 && d2 >= 0 && d6 <= 0)
    {
        return a + (d2 / (d2 - d6)) * ac;
    }
    const Real va = d3 * d6 - d5 * d4;
    if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    {
        return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
    }
    const Real sum = va + vb + vc;
    if (!(sum > 0)) // degenerate (collinear) triangle whose tests above all failed by rounding: its nearest vertex
    {
        const Real da = ap.squaredNorm();
        const Real db = bp.squaredNorm();
        const Real dc = cp.squaredNorm();
        return da <= db && da <= dc ? a : (db <= dc ? b : c);
    }
    const Real v = vb / sum;
    const Real w = vc / sum;
    return a + ab * v + ac * w;
}
} // namespace masse::bridge
