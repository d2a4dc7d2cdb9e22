#pragma once
/// The closest points of two segments (Ericson, Real-Time Collision Detection, 5.1.9): the narrowphase of a sheet
/// edge against an obstacle edge (EdgeContact.h). Closed form: a 2x2 solve for the lines' closest points, clamped to
/// the segments in the order that keeps the answer the true minimum.

#include "core/Types.h"

#include <algorithm>

namespace masse
{
/// Where along each segment the two are closest: the points are p1 + s (q1 - p1) and p2 + t (q2 - p2), s and t in
/// [0, 1]; an end is returned exactly as 0 or 1.
struct SegmentParameters
{
    Real s = 0;
    Real t = 0;
};

inline SegmentParameters closestPointsOfSegments(const Vec3& p1, const Vec3& q1, const Vec3& p2, const Vec3& q2)
{
    const Vec3 d1 = q1 - p1;
    const Vec3 d2 = q2 - p2;
    const Vec3 r = p1 - p2;
    const Real a = d1.squaredNorm();
    const Real e = d2.squaredNorm();
    const Real f = d2.dot(r);
    const auto clamp01 = [](Real v) { return std::clamp(v, Real(0), Real(1)); };
    if (!(a > 0) && !(e > 0))
    {
        return {0, 0}; // both are points
    }
    if (!(a > 0))
    {
        return {0, clamp01(f / e)};
    }
    const Real c = d1.dot(r);
    if (!(e > 0))
    {
        return {clamp01(-c / a), 0};
    }
    const Real b = d1.dot(d2);
    const Real denominator = a * e - b * b;
    // Parallel (to rounding): any s gives a closest pair; the first end is as good as any.
    Real s = denominator > Real(1e-12) * a * e ? clamp01((b * f - c * e) / denominator) : Real(0);
    Real t = (b * s + f) / e;
    if (t < 0)
    {
        t = 0;
        s = clamp01(-c / a);
    }
    else if (t > 1)
    {
        t = 1;
        s = clamp01((b - c) / a);
    }
    return {s, t};
}
} // namespace masse
