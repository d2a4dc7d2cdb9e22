#include "FacePlanesOfEight.h"

#include "core/forces/SimdColumns.h"
#include "core/forces/SimdPath.h"

#include <cassert>

namespace masse::bridge
{
#if MASSE_SIMD_COLUMNS
namespace
{
using namespace simd;

/// Eigen's cross product a x b, coordinate by coordinate: (a1 b2 - a2 b1, a2 b0 - a0 b2, a0 b1 - a1 b0).
MASSE_AVX512 inline Columns cross(__m512d ax, __m512d ay, __m512d az, const Columns& b)
{
    return {_mm512_sub_pd(_mm512_mul_pd(ay, b.z), _mm512_mul_pd(az, b.y)),
            _mm512_sub_pd(_mm512_mul_pd(az, b.x), _mm512_mul_pd(ax, b.z)),
            _mm512_sub_pd(_mm512_mul_pd(ax, b.y), _mm512_mul_pd(ay, b.x))};
}

/// Eigen's quaternion rotation (Quaternion.h, _transformVector) of v by the quaternion (w; qx, qy, qz), lane by lane
/// in its order: uv = q.vec() x v; uv += uv; v + w uv + q.vec() x uv.
MASSE_AVX512 inline Columns rotated(__m512d w, __m512d qx, __m512d qy, __m512d qz, const Columns& v)
{
    Columns uv = cross(qx, qy, qz, v);
    uv = {_mm512_add_pd(uv.x, uv.x), _mm512_add_pd(uv.y, uv.y), _mm512_add_pd(uv.z, uv.z)};
    const Columns turn = cross(qx, qy, qz, uv);
    return {_mm512_add_pd(_mm512_add_pd(v.x, _mm512_mul_pd(w, uv.x)), turn.x),
            _mm512_add_pd(_mm512_add_pd(v.y, _mm512_mul_pd(w, uv.y)), turn.y),
            _mm512_add_pd(_mm512_add_pd(v.z, _mm512_mul_pd(w, uv.z)), turn.z)};
}

MASSE_AVX512 inline Columns broadcast(const Vec3& v)
{
    return {_mm512_set1_pd(v.x()), _mm512_set1_pd(v.y()), _mm512_set1_pd(v.z())};
}

/// facePlaneDistance's height of the points over a face's plane: normal . point - offset.
MASSE_AVX512 inline __m512d heightOver(const Face& face, const Columns& point)
{
    return _mm512_sub_pd(dot(broadcast(face.normal), point.x, point.y, point.z), _mm512_set1_pd(face.offset));
}

MASSE_AVX512 void facePlanesOfEightAvx512(const ObstacleGeometry& g, const Pose& pose, const Vec3* centres,
                                          FacePlanesOfEight& out)
{
    const Eigen::Quaternion<Real>& q = pose.orientation;
    const __m512d w = _mm512_set1_pd(q.w());
    const __m512d qx = _mm512_set1_pd(q.x());
    const __m512d qy = _mm512_set1_pd(q.y());
    const __m512d qz = _mm512_set1_pd(q.z());
    const Columns origin = broadcast(pose.position);

    // closestFeatures' local = toLocal * (centre - position), toLocal being the conjugate: the same w, the vector
    // part's signs flipped.
    const Columns centre = loadColumns(centres[0].data());
    const Columns relative{_mm512_sub_pd(centre.x, origin.x), _mm512_sub_pd(centre.y, origin.y),
                           _mm512_sub_pd(centre.z, origin.z)};
    const Columns local = rotated(w, negated(qx), negated(qy), negated(qz), relative);

    // facePlaneDistance: the face the point is farthest in front of, the first such on ties.
    __m512d height = heightOver(g.faces[0], local);
    __m512i nearest = _mm512_setzero_si512();
    Columns normal = broadcast(g.faces[0].normal);
    for (std::size_t f = 1; f < g.faces.size(); ++f)
    {
        const __m512d h = heightOver(g.faces[f], local);
        const __mmask8 higher = _mm512_cmp_pd_mask(h, height, _CMP_GT_OQ);
        height = _mm512_mask_blend_pd(higher, height, h);
        nearest = _mm512_mask_blend_epi64(higher, nearest, _mm512_set1_epi64(std::int64_t(f)));
        const Columns n = broadcast(g.faces[f].normal);
        normal = {_mm512_mask_blend_pd(higher, normal.x, n.x), _mm512_mask_blend_pd(higher, normal.y, n.y),
                  _mm512_mask_blend_pd(higher, normal.z, n.z)};
    }
    const Columns projection{_mm512_sub_pd(local.x, _mm512_mul_pd(height, normal.x)),
                             _mm512_sub_pd(local.y, _mm512_mul_pd(height, normal.y)),
                             _mm512_sub_pd(local.z, _mm512_mul_pd(height, normal.z))};
    // In front of the face, the projection must lie strictly behind every other face's plane.
    const __mmask8 inFront = _mm512_cmp_pd_mask(height, _mm512_setzero_pd(), _CMP_GT_OQ);
    __mmask8 onEdge = 0;
    for (std::size_t f = 0; f < g.faces.size(); ++f)
    {
        const __mmask8 other = _mm512_cmpneq_epi64_mask(nearest, _mm512_set1_epi64(std::int64_t(f)));
        const __m512d h = heightOver(g.faces[f], projection);
        onEdge |= __mmask8(other & _mm512_cmp_pd_mask(h, _mm512_setzero_pd(), _CMP_GE_OQ));
    }
    out.found = std::uint8_t(~__mmask8(inFront & onEdge));

    // closestFeatures' plane: the face's normal and the nearest point rotated back to the world, the point moved by
    // the position, and the offset normal . point.
    const Columns worldNormal = rotated(w, qx, qy, qz, normal);
    const Columns turned = rotated(w, qx, qy, qz, projection);
    const Columns point{_mm512_add_pd(turned.x, origin.x), _mm512_add_pd(turned.y, origin.y),
                        _mm512_add_pd(turned.z, origin.z)};
    _mm512_store_pd(out.distance, height);
    _mm512_store_pd(out.normalX, worldNormal.x);
    _mm512_store_pd(out.normalY, worldNormal.y);
    _mm512_store_pd(out.normalZ, worldNormal.z);
    _mm512_store_pd(out.pointX, point.x);
    _mm512_store_pd(out.pointY, point.y);
    _mm512_store_pd(out.pointZ, point.z);
    _mm512_store_pd(out.offset, dot(worldNormal, point.x, point.y, point.z));
    _mm512_store_si512(out.face, nearest);
}
} // namespace
#endif

bool facePlanesOfEightAvailable()
{
#if MASSE_SIMD_COLUMNS
    return activeSimdPath() == SimdPath::Avx512;
#else
    return false;
#endif
}

void facePlanesOfEight(const ObstacleGeometry& g, const Pose& pose, const Vec3* centres, FacePlanesOfEight& out)
{
    assert(g.convex && !g.faces.empty() && facePlanesOfEightAvailable());
#if MASSE_SIMD_COLUMNS
    facePlanesOfEightAvx512(g, pose, centres, out);
#else
    (void)g;
    (void)pose;
    (void)centres;
    out.found = 0;
#endif
}
} // namespace masse::bridge
