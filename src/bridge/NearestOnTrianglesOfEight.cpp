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

/// The eight triangles' corners (rows 0 to 8: a's x, y, z, then b's and c's) and normals (rows 9 to 11), a row per
/// coordinate and a column per lane; lanes past `count` repeat the first triangle, and are masked off at the end.
struct LaneValues
{
    alignas(64) Real row[12][8];
};

void gatherLanes(const std::vector<std::array<Vec3, 3>>& corners, const std::vector<Vec3>& normals,
                 const std::int32_t* triangles, int count, LaneValues& values)
{
    for (int lane = 0; lane < 8; ++lane)
    {
        const auto t = std::size_t(triangles[lane < count ? lane : 0]);
        for (int corner = 0; corner < 3; ++corner)
        {
            for (int axis = 0; axis < 3; ++axis)
            {
                values.row[3 * corner + axis][lane] = corners[t][std::size_t(corner)][axis];
            }
        }
        for (int axis = 0; axis < 3; ++axis)
        {
            values.row[9 + axis][lane] = normals[t][axis];
        }
    }
}

MASSE_AVX512 void nearestOnTrianglesOfEightAvx512(const LaneValues& lanes, int count, const Vec3& centre,
                                                  Real rejectBeyond, NearestOnTrianglesOfEight& out)
{
    const auto& values = lanes.row;
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

// The same kernel on the AVX2 path, four lanes a register: each lane does the same IEEE operations in the same order
// (min, max, compares and square roots are the same instructions four lanes wide; a mask is a vector of all-ones
// lanes, a masked move a blend, |x| the sign bit cleared), so each lane has the AVX-512 kernel's bits, the scalar
// code's.

struct Columns4
{
    __m256d x;
    __m256d y;
    __m256d z;
};

MASSE_AVX2 inline Columns4 difference4(const Columns4& u, const Columns4& v)
{
    return {_mm256_sub_pd(u.x, v.x), _mm256_sub_pd(u.y, v.y), _mm256_sub_pd(u.z, v.z)};
}

/// Eigen's u.dot(v) for 3-vectors: (ux vx + uy vy) + uz vz.
MASSE_AVX2 inline __m256d dot4(const Columns4& u, const Columns4& v)
{
    return _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(u.x, v.x), _mm256_mul_pd(u.y, v.y)), _mm256_mul_pd(u.z, v.z));
}

struct Weights4
{
    __m256d a;
    __m256d b;
    __m256d c;
    __m256d open; ///< all-ones in the lanes no case has taken yet
};

MASSE_AVX2 inline void take4(Weights4& w, __m256d condition, __m256d wa, __m256d wb, __m256d wc)
{
    const __m256d lanes = _mm256_and_pd(w.open, condition);
    w.a = _mm256_blendv_pd(w.a, wa, lanes);
    w.b = _mm256_blendv_pd(w.b, wb, lanes);
    w.c = _mm256_blendv_pd(w.c, wc, lanes);
    w.open = _mm256_andnot_pd(lanes, w.open);
}

MASSE_AVX2 inline __m256d atMost4(__m256d a, __m256d b)
{
    return _mm256_cmp_pd(a, b, _CMP_LE_OQ);
}
MASSE_AVX2 inline __m256d atLeast4(__m256d a, __m256d b)
{
    return _mm256_cmp_pd(a, b, _CMP_GE_OQ);
}

MASSE_AVX2 inline __m256d outside4(__m256d a, __m256d b, __m256d c, __m256d p)
{
    const __m256d low = _mm256_min_pd(_mm256_min_pd(a, b), c);
    const __m256d high = _mm256_max_pd(_mm256_max_pd(a, b), c);
    return _mm256_max_pd(_mm256_max_pd(_mm256_sub_pd(low, p), _mm256_sub_pd(p, high)), _mm256_setzero_pd());
}

MASSE_AVX2 inline __m256d weighted4(__m256d wa, __m256d wb, __m256d wc, __m256d a, __m256d b, __m256d c)
{
    return _mm256_add_pd(_mm256_add_pd(_mm256_mul_pd(wa, a), _mm256_mul_pd(wb, b)), _mm256_mul_pd(wc, c));
}

/// Lanes first to first + 3 of the eight.
MASSE_AVX2 void nearestOnTrianglesOfFourAvx2(const LaneValues& lanes, int first, int count, const Vec3& centre,
                                             Real rejectBeyond, NearestOnTrianglesOfEight& out)
{
    __m256d row[12];
    for (int k = 0; k < 12; ++k)
    {
        row[k] = _mm256_load_pd(lanes.row[k] + first);
    }
    const Columns4 a{row[0], row[1], row[2]};
    const Columns4 b{row[3], row[4], row[5]};
    const Columns4 c{row[6], row[7], row[8]};
    const Columns4 normal{row[9], row[10], row[11]};
    const Columns4 p{_mm256_set1_pd(centre.x()), _mm256_set1_pd(centre.y()), _mm256_set1_pd(centre.z())};
    const __m256d zero = _mm256_setzero_pd();
    const __m256d one = _mm256_set1_pd(1);
    const __m256d all = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));

    const Columns4 away{outside4(a.x, b.x, c.x, p.x), outside4(a.y, b.y, c.y, p.y), outside4(a.z, b.z, c.z, p.z)};
    const __m256d boxDistance2 = dot4(away, away);
    const Columns4 ap = difference4(p, a);
    const __m256d planeDistance = _mm256_andnot_pd(_mm256_set1_pd(-0.0), dot4(normal, ap));
    const __m256d counted =
        _mm256_castsi256_pd(_mm256_cmpgt_epi64(_mm256_set1_epi64x(count - first), _mm256_setr_epi64x(0, 1, 2, 3)));
    const __m256d passed = _mm256_andnot_pd(
        _mm256_or_pd(_mm256_cmp_pd(boxDistance2, _mm256_set1_pd(rejectBeyond * rejectBeyond), _CMP_GT_OQ),
                     _mm256_cmp_pd(planeDistance, _mm256_set1_pd(rejectBeyond), _CMP_GT_OQ)),
        counted);

    const Columns4 ab = difference4(b, a);
    const Columns4 ac = difference4(c, a);
    const __m256d d1 = dot4(ab, ap);
    const __m256d d2 = dot4(ac, ap);
    Weights4 w{zero, zero, zero, passed};
    take4(w, _mm256_and_pd(atMost4(d1, zero), atMost4(d2, zero)), one, zero, zero); // vertex a

    const Columns4 bp = difference4(p, b);
    const __m256d d3 = dot4(ab, bp);
    const __m256d d4 = dot4(ac, bp);
    take4(w, _mm256_and_pd(atLeast4(d3, zero), atMost4(d4, d3)), zero, one, zero); // vertex b

    const __m256d vc = _mm256_sub_pd(_mm256_mul_pd(d1, d4), _mm256_mul_pd(d3, d2));
    const __m256d vAB = _mm256_div_pd(d1, _mm256_sub_pd(d1, d3));
    take4(w, _mm256_and_pd(_mm256_and_pd(atMost4(vc, zero), atLeast4(d1, zero)), atMost4(d3, zero)),
          _mm256_sub_pd(one, vAB), vAB, zero); // edge ab

    const Columns4 cp = difference4(p, c);
    const __m256d d5 = dot4(ab, cp);
    const __m256d d6 = dot4(ac, cp);
    take4(w, _mm256_and_pd(atLeast4(d6, zero), atMost4(d5, d6)), zero, zero, one); // vertex c

    const __m256d vb = _mm256_sub_pd(_mm256_mul_pd(d5, d2), _mm256_mul_pd(d1, d6));
    const __m256d wAC = _mm256_div_pd(d2, _mm256_sub_pd(d2, d6));
    take4(w, _mm256_and_pd(_mm256_and_pd(atMost4(vb, zero), atLeast4(d2, zero)), atMost4(d6, zero)),
          _mm256_sub_pd(one, wAC), zero, wAC); // edge ac

    const __m256d va = _mm256_sub_pd(_mm256_mul_pd(d3, d6), _mm256_mul_pd(d5, d4));
    const __m256d d43 = _mm256_sub_pd(d4, d3);
    const __m256d d56 = _mm256_sub_pd(d5, d6);
    const __m256d wBC = _mm256_div_pd(d43, _mm256_add_pd(d43, d56));
    take4(w, _mm256_and_pd(_mm256_and_pd(atMost4(va, zero), atLeast4(d43, zero)), atLeast4(d56, zero)), zero,
          _mm256_sub_pd(one, wBC), wBC); // edge bc

    const __m256d sum = _mm256_add_pd(_mm256_add_pd(va, vb), vc);
    const __m256d degenerate = _mm256_and_pd(w.open, _mm256_cmp_pd(sum, zero, _CMP_NGT_UQ));
    w.open = _mm256_andnot_pd(degenerate, w.open);
    const __m256d denominator = _mm256_div_pd(one, sum);
    const __m256d v = _mm256_mul_pd(vb, denominator);
    const __m256d wFace = _mm256_mul_pd(vc, denominator);
    take4(w, all, _mm256_sub_pd(_mm256_sub_pd(one, v), wFace), v, wFace); // the face

    const Columns4 nearest{weighted4(w.a, w.b, w.c, a.x, b.x, c.x), weighted4(w.a, w.b, w.c, a.y, b.y, c.y),
                           weighted4(w.a, w.b, w.c, a.z, b.z, c.z)};
    _mm256_store_pd(out.nearestX + first, nearest.x);
    _mm256_store_pd(out.nearestY + first, nearest.y);
    _mm256_store_pd(out.nearestZ + first, nearest.z);
    const Columns4 offset = difference4(p, nearest);
    const __m256d gap = _mm256_sqrt_pd(dot4(offset, offset));
    _mm256_store_pd(out.gap + first, gap);
    _mm256_store_pd(out.directionX + first, _mm256_div_pd(offset.x, gap));
    _mm256_store_pd(out.directionY + first, _mm256_div_pd(offset.y, gap));
    _mm256_store_pd(out.directionZ + first, _mm256_div_pd(offset.z, gap));
    out.degenerate = std::uint8_t(out.degenerate | unsigned(_mm256_movemask_pd(degenerate)) << unsigned(first));
    out.near =
        std::uint8_t(out.near | unsigned(_mm256_movemask_pd(_mm256_andnot_pd(degenerate, passed))) << unsigned(first));
}
} // namespace
#endif

bool nearestOnTrianglesOfEightAvailable()
{
#if MASSE_SIMD_COLUMNS
    return activeSimdPath() == SimdPath::Avx512 || activeSimdPath() == SimdPath::Avx2;
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
    LaneValues lanes;
    gatherLanes(corners, normals, triangles, count, lanes);
    if (activeSimdPath() == SimdPath::Avx512)
    {
        nearestOnTrianglesOfEightAvx512(lanes, count, centre, rejectBeyond, out);
        return;
    }
    out.near = 0;
    out.degenerate = 0;
    nearestOnTrianglesOfFourAvx2(lanes, 0, count, centre, rejectBeyond, out);
    if (count > 4)
    {
        nearestOnTrianglesOfFourAvx2(lanes, 4, count, centre, rejectBeyond, out);
    }
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
