#include "NearestOnTrianglesOfEight.h"

#include "core/forces/SimdColumns.h"
#include "core/forces/SimdPath.h"

#include <cassert>

namespace masse::bridge
{
#if MASSE_SIMD_COLUMNS
namespace
{
using namespace simd;

MASSE_AVX512 inline Columns difference(const Columns& u, const Columns& v)
{
    return {_mm512_sub_pd(u.x, v.x), _mm512_sub_pd(u.y, v.y), _mm512_sub_pd(u.z, v.z)};
}

/// Eigen's u.dot(v) for 3-vectors: (ux vx + uy vy) + uz vz.
MASSE_AVX512 inline __m512d dot(const Columns& u, const Columns& v)
{
    return simd::dot(u, v.x, v.y, v.z);
}

/// closestPointWeights' weights of the three corners, lane by lane, as its cases give them, and the lanes no case has
/// taken yet.
struct Weights
{
    __m512d a;
    __m512d b;
    __m512d c;
    __mmask8 open;
};

/// The scalar code's `if (condition) return (wa, wb, wc);`: the open lanes where `condition` holds take those weights
/// and are closed to the later cases.
MASSE_AVX512 inline void take(Weights& w, __mmask8 condition, __m512d wa, __m512d wb, __m512d wc)
{
    const auto lanes = __mmask8(w.open & condition);
    w.a = _mm512_mask_mov_pd(w.a, lanes, wa);
    w.b = _mm512_mask_mov_pd(w.b, lanes, wb);
    w.c = _mm512_mask_mov_pd(w.c, lanes, wc);
    w.open = __mmask8(w.open & ~lanes);
}

/// The scalar code's a <= b and a >= b, lane by lane (false where either is NaN, as there).
MASSE_AVX512 inline __mmask8 atMost(__m512d a, __m512d b)
{
    return _mm512_cmp_pd_mask(a, b, _CMP_LE_OQ);
}
MASSE_AVX512 inline __mmask8 atLeast(__m512d a, __m512d b)
{
    return _mm512_cmp_pd_mask(a, b, _CMP_GE_OQ);
}

/// The zero-masking forms of min and max on all lanes: GCC 12's plain _mm512_min_pd and _mm512_max_pd merge into an
/// "undefined" vector, which its own -Wmaybe-uninitialized reports.
MASSE_AVX512 inline __m512d minimum(__m512d a, __m512d b)
{
    return _mm512_maskz_min_pd(__mmask8(0xFF), a, b);
}
MASSE_AVX512 inline __m512d maximum(__m512d a, __m512d b)
{
    return _mm512_maskz_max_pd(__mmask8(0xFF), a, b);
}

/// Along one axis, how far p lies outside the box of a, b and c (0 inside): TriangleTest's
/// max(min(a, b, c) - p, p - max(a, b, c), 0). Its values only decide whether a triangle is turned away, the same
/// way as the scalar test's (the two may differ in the sign of a zero, which the decision does not see).
MASSE_AVX512 inline __m512d outside(__m512d a, __m512d b, __m512d c, __m512d p)
{
    const __m512d low = minimum(minimum(a, b), c);
    const __m512d high = maximum(maximum(a, b), c);
    return maximum(maximum(_mm512_sub_pd(low, p), _mm512_sub_pd(p, high)), _mm512_setzero_pd());
}

/// (wa a + wb b) + wc c, one coordinate.
MASSE_AVX512 inline __m512d weighted(__m512d wa, __m512d wb, __m512d wc, __m512d a, __m512d b, __m512d c)
{
    return _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(wa, a), _mm512_mul_pd(wb, b)), _mm512_mul_pd(wc, c));
}

MASSE_AVX512 void nearestOnTrianglesOfEightAvx512(const std::vector<std::array<Vec3, 3>>& corners,
                                                  const std::vector<Vec3>& normals, const std::int32_t* triangles,
                                                  int count, const Vec3& centre, Real rejectBeyond,
                                                  NearestOnTrianglesOfEight& out)
{
    // The eight triangles' corners and normals, one register per coordinate; lanes past `count` repeat the first
    // triangle and are masked off at the end.
    alignas(64) Real values[12][8];
    for (int lane = 0; lane < 8; ++lane)
    {
        const auto t = std::size_t(triangles[lane < count ? lane : 0]);
        for (int corner = 0; corner < 3; ++corner)
        {
            for (int axis = 0; axis < 3; ++axis)
            {
                values[3 * corner + axis][lane] = corners[t][std::size_t(corner)][axis];
            }
        }
        for (int axis = 0; axis < 3; ++axis)
        {
            values[9 + axis][lane] = normals[t][axis];
        }
    }
    const Columns a{_mm512_load_pd(values[0]), _mm512_load_pd(values[1]), _mm512_load_pd(values[2])};
    const Columns b{_mm512_load_pd(values[3]), _mm512_load_pd(values[4]), _mm512_load_pd(values[5])};
    const Columns c{_mm512_load_pd(values[6]), _mm512_load_pd(values[7]), _mm512_load_pd(values[8])};
    const Columns normal{_mm512_load_pd(values[9]), _mm512_load_pd(values[10]), _mm512_load_pd(values[11])};
    const Columns p{_mm512_set1_pd(centre.x()), _mm512_set1_pd(centre.y()), _mm512_set1_pd(centre.z())};
    const __m512d zero = _mm512_setzero_pd();
    const __m512d one = _mm512_set1_pd(1);

    // TriangleTest's tests: the distance from the centre to the triangle's box, and to its plane.
    const Columns away{outside(a.x, b.x, c.x, p.x), outside(a.y, b.y, c.y, p.y), outside(a.z, b.z, c.z, p.z)};
    const __m512d boxDistance2 = dot(away, away);
    const Columns ap = difference(p, a);
    const __m512d planeDistance = _mm512_abs_pd(dot(normal, ap));
    const __m512d reject = _mm512_set1_pd(rejectBeyond);
    const __mmask8 passed =
        __mmask8(((1u << unsigned(count)) - 1u) &
                 ~unsigned(_mm512_cmp_pd_mask(boxDistance2, _mm512_set1_pd(rejectBeyond * rejectBeyond), _CMP_GT_OQ)) &
                 ~unsigned(_mm512_cmp_pd_mask(planeDistance, reject, _CMP_GT_OQ)));

    // closestPointWeights, region by region in its order.
    const Columns ab = difference(b, a);
    const Columns ac = difference(c, a);
    const __m512d d1 = dot(ab, ap);
    const __m512d d2 = dot(ac, ap);
    Weights w{zero, zero, zero, passed};
    take(w, atMost(d1, zero) & atMost(d2, zero), one, zero, zero); // vertex a

    const Columns bp = difference(p, b);
    const __m512d d3 = dot(ab, bp);
    const __m512d d4 = dot(ac, bp);
    take(w, atLeast(d3, zero) & atMost(d4, d3), zero, one, zero); // vertex b

    const __m512d vc = _mm512_sub_pd(_mm512_mul_pd(d1, d4), _mm512_mul_pd(d3, d2));
    const __m512d vAB = _mm512_div_pd(d1, _mm512_sub_pd(d1, d3));
    take(w, atMost(vc, zero) & atLeast(d1, zero) & atMost(d3, zero), _mm512_sub_pd(one, vAB), vAB, zero); // edge ab

    const Columns cp = difference(p, c);
    const __m512d d5 = dot(ab, cp);
    const __m512d d6 = dot(ac, cp);
    take(w, atLeast(d6, zero) & atMost(d5, d6), zero, zero, one); // vertex c

    const __m512d vb = _mm512_sub_pd(_mm512_mul_pd(d5, d2), _mm512_mul_pd(d1, d6));
    const __m512d wAC = _mm512_div_pd(d2, _mm512_sub_pd(d2, d6));
    take(w, atMost(vb, zero) & atLeast(d2, zero) & atMost(d6, zero), _mm512_sub_pd(one, wAC), zero, wAC); // edge ac

    const __m512d va = _mm512_sub_pd(_mm512_mul_pd(d3, d6), _mm512_mul_pd(d5, d4));
    const __m512d d43 = _mm512_sub_pd(d4, d3);
    const __m512d d56 = _mm512_sub_pd(d5, d6);
    const __m512d wBC = _mm512_div_pd(d43, _mm512_add_pd(d43, d56));
    take(w, atMost(va, zero) & atLeast(d43, zero) & atLeast(d56, zero), zero, _mm512_sub_pd(one, wBC), wBC); // edge bc

    const __m512d sum = _mm512_add_pd(_mm512_add_pd(va, vb), vc);
    const auto degenerate = __mmask8(w.open & _mm512_cmp_pd_mask(sum, zero, _CMP_NGT_UQ));
    w.open = __mmask8(w.open & ~degenerate);
    const __m512d denominator = _mm512_div_pd(one, sum);
    const __m512d v = _mm512_mul_pd(vb, denominator);
    const __m512d wFace = _mm512_mul_pd(vc, denominator);
    take(w, __mmask8(0xFF), _mm512_sub_pd(_mm512_sub_pd(one, v), wFace), v, wFace); // the face

    // closestPointOnTriangle's w.x() a + w.y() b + w.z() c, coordinate by coordinate.
    const Columns nearest{weighted(w.a, w.b, w.c, a.x, b.x, c.x), weighted(w.a, w.b, w.c, a.y, b.y, c.y),
                          weighted(w.a, w.b, w.c, a.z, b.z, c.z)};
    _mm512_store_pd(out.nearestX, nearest.x);
    _mm512_store_pd(out.nearestY, nearest.y);
    _mm512_store_pd(out.nearestZ, nearest.z);
    // TriangleTest::take's offset, its norm (Eigen's: the square root of (x x + y y) + z z; zero-masking, as in
    // minimum()) and its direction.
    const Columns offset = difference(p, nearest);
    const __m512d gap = _mm512_maskz_sqrt_pd(__mmask8(0xFF), dot(offset, offset));
    _mm512_store_pd(out.gap, gap);
    _mm512_store_pd(out.directionX, _mm512_div_pd(offset.x, gap));
    _mm512_store_pd(out.directionY, _mm512_div_pd(offset.y, gap));
    _mm512_store_pd(out.directionZ, _mm512_div_pd(offset.z, gap));
    out.degenerate = degenerate;
    out.near = __mmask8(passed & ~degenerate);
}
} // namespace
#endif

bool nearestOnTrianglesOfEightAvailable()
{
#if MASSE_SIMD_COLUMNS
    return activeSimdPath() == SimdPath::Avx512;
#else
    return false;
#endif
}

void nearestOnTrianglesOfEight(const std::vector<std::array<Vec3, 3>>& corners, const std::vector<Vec3>& normals,
                               const std::int32_t* triangles, int count, const Vec3& centre, Real rejectBeyond,
                               NearestOnTrianglesOfEight& out)
{
    assert(count >= 1 && count <= 8 && nearestOnTrianglesOfEightAvailable());
#if MASSE_SIMD_COLUMNS
    nearestOnTrianglesOfEightAvx512(corners, normals, triangles, count, centre, rejectBeyond, out);
#else
    (void)corners;
    (void)normals;
    (void)triangles;
    (void)count;
    (void)centre;
    (void)rejectBeyond;
    out = {};
#endif
}
} // namespace masse::bridge
