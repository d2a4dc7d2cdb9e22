#pragma once
/// AVX-512 helpers shared by the kernels that take eight masses at once (contact projection, contact detection):
/// eight 3-vectors as they lie in memory (x0 y0 z0 x1 ...) rearranged in registers into one register per coordinate
/// and back, and the scalar code's dot product and negation on eight lanes. Every helper moves bits or does the scalar
/// code's IEEE operations in its order, so a lane's result has the bits of the scalar code's.
///
/// The functions carry their own target attribute: a file built for the baseline x86-64 can call them behind a check
/// of activeSimdPath() (SimdPath.h). MASSE_SIMD_COLUMNS is 0 where they do not exist (not x86-64, or not GCC/Clang).

#include "core/Types.h"

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>

#include <cstdint>
#define MASSE_SIMD_COLUMNS 1
#define MASSE_AVX512 __attribute__((target("avx512f")))
/// The AVX2 path's own four-lane kernels (mesh contact) carry this one.
#define MASSE_AVX2 __attribute__((target("avx2")))

namespace masse::simd
{
static_assert(sizeof(Vec3) == 3 * sizeof(Real), "the kernels below read eight masses' 3-vectors as 24 Reals");

/// Eight consecutive 3-vectors (x0 y0 z0 x1 ... z7: three registers' worth) as one register per coordinate.
struct Columns
{
    __m512d x;
    __m512d y;
    __m512d z;
};

MASSE_AVX512 inline Columns loadColumns(const Real* p)
{
    const __m512d a = _mm512_loadu_pd(p);
    const __m512d b = _mm512_loadu_pd(p + 8);
    const __m512d c = _mm512_loadu_pd(p + 16);
    // Each coordinate's first five or six values come from a and b, the rest from c.
    const __m512d xab = _mm512_permutex2var_pd(a, _mm512_setr_epi64(0, 3, 6, 9, 12, 15, 0, 0), b);
    const __m512d yab = _mm512_permutex2var_pd(a, _mm512_setr_epi64(1, 4, 7, 10, 13, 0, 0, 0), b);
    const __m512d zab = _mm512_permutex2var_pd(a, _mm512_setr_epi64(2, 5, 8, 11, 14, 0, 0, 0), b);
    return {_mm512_permutex2var_pd(xab, _mm512_setr_epi64(0, 1, 2, 3, 4, 5, 10, 13), c),
            _mm512_permutex2var_pd(yab, _mm512_setr_epi64(0, 1, 2, 3, 4, 8, 11, 14), c),
            _mm512_permutex2var_pd(zab, _mm512_setr_epi64(0, 1, 2, 3, 4, 9, 12, 15), c)};
}

/// Three registers of eight 3-vectors as they lie in memory: x0 y0 z0 x1 y1 z1 x2 y2 | z2 x3 ... | ... x7 y7 z7.
struct Rows
{
    __m512d first;
    __m512d second;
    __m512d third;
};

/// The inverse of loadColumns, in registers.
MASSE_AVX512 inline Rows rowsOf(const Columns& v)
{
    // x and y first, then z.
    const __m512d xya = _mm512_permutex2var_pd(v.x, _mm512_setr_epi64(0, 8, 0, 1, 9, 0, 2, 10), v.y);
    const __m512d xyb = _mm512_permutex2var_pd(v.x, _mm512_setr_epi64(0, 3, 11, 0, 4, 12, 0, 5), v.y);
    const __m512d xyc = _mm512_permutex2var_pd(v.x, _mm512_setr_epi64(13, 0, 6, 14, 0, 7, 15, 0), v.y);
    return {_mm512_permutex2var_pd(xya, _mm512_setr_epi64(0, 1, 8, 3, 4, 9, 6, 7), v.z),
            _mm512_permutex2var_pd(xyb, _mm512_setr_epi64(10, 1, 2, 11, 4, 5, 12, 7), v.z),
            _mm512_permutex2var_pd(xyc, _mm512_setr_epi64(0, 13, 2, 3, 14, 5, 6, 15), v.z)};
}

MASSE_AVX512 inline void storeColumns(Real* p, const Columns& v)
{
    const Rows rows = rowsOf(v);
    _mm512_storeu_pd(p, rows.first);
    _mm512_storeu_pd(p + 8, rows.second);
    _mm512_storeu_pd(p + 16, rows.third);
}

MASSE_AVX512 inline __m512d negated(__m512d a)
{
    // Flips the sign bit, as the scalar negation does (0 - a would give +0 for +0).
    return _mm512_castsi512_pd(
        _mm512_xor_si512(_mm512_castpd_si512(a), _mm512_set1_epi64(std::int64_t(0x8000000000000000ULL))));
}

/// The dot product of normal n with (x, y, z) in the scalar code's order: (nx x + ny y) + nz z.
MASSE_AVX512 inline __m512d dot(const Columns& n, __m512d x, __m512d y, __m512d z)
{
    return _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(n.x, x), _mm512_mul_pd(n.y, y)), _mm512_mul_pd(n.z, z));
}

} // namespace masse::simd
#else
#define MASSE_SIMD_COLUMNS 0
#endif
