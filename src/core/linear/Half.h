#pragma once
/// IEEE binary16 ("half") values, for the Cholesky factor the triangular solves stream (see MassBlockRows.h). The
/// rounding to half is done in software (halfFromReal), the same bits whatever the processor, and on the SIMD paths
/// that have F16C by its conversion (halvesFromFloatsF16c), which rounds the same way (HalfTest checks that they
/// agree); reading a half back is exact on every SIMD path.

#include <cstdint>
#include <cstring>
#include <vector>

#if defined(__x86_64__) && defined(__GNUC__)
#include <immintrin.h>
#endif

namespace masse
{
/// `value` rounded to the nearest binary16 (ties to even), as its bits; magnitudes past the largest finite half
/// (65504) are clamped to it rather than made infinite, and those below the smallest subnormal (2^-24) flush to zero
/// as the rounding gives. Direct from double, so there is no double rounding through float.
inline std::uint16_t halfFromReal(double value)
{
    std::uint64_t bits;
    std::memcpy(&bits, &value, sizeof bits);
    const std::uint64_t sign = bits & 0x8000000000000000ull;
    const std::uint64_t magnitude = bits ^ sign;
    const auto signBit = std::uint16_t(sign >> 48);
    constexpr std::uint64_t clampFrom = 0x40EFFE0000000000ull;      // 65520: rounds to infinity from here up (and NaN)
    constexpr std::uint64_t smallestNormal = 0x3F10000000000000ull; // 2^-14
    if (magnitude >= clampFrom)
    {
        return std::uint16_t(signBit | 0x7BFF);
    }
    if (magnitude < smallestNormal)
    {
        // Adding 2^28, whose last bit is worth 2^-24 (a half subnormal's step), rounds to a subnormal's steps.
        double magnitudeValue;
        std::memcpy(&magnitudeValue, &magnitude, sizeof magnitudeValue);
        const double shifted = magnitudeValue + 268435456.0;
        std::uint64_t shiftedBits;
        std::memcpy(&shiftedBits, &shifted, sizeof shiftedBits);
        return std::uint16_t(signBit | std::uint16_t(shiftedBits - 0x41B0000000000000ull));
    }
    // Rebias the exponent (1023 to 15) and round the 52-bit mantissa to 10 bits, ties to even; a carry out of the
    // mantissa moves into the exponent, as it should.
    const std::uint64_t oddLast = (magnitude >> 42) & 1;
    const std::uint64_t rounded = magnitude - (std::uint64_t(1023 - 15) << 52) + ((1ull << 41) - 1) + oddLast;
    return std::uint16_t(signBit | std::uint16_t(rounded >> 42));
}

/// The binary16 `bits` as a float (exact; never infinite or NaN here).
inline float floatFromHalf(std::uint16_t bits)
{
    const std::uint32_t sign = std::uint32_t(bits & 0x8000) << 16;
    const std::uint32_t exponent = (bits >> 10) & 0x1F;
    const std::uint32_t mantissa = bits & 0x3FF;
    if (exponent == 0)
    {
        const float magnitude = float(mantissa) * 5.9604644775390625e-8f; // 2^-24, exact
        return sign ? -magnitude : magnitude;
    }
    const std::uint32_t floatBits = sign | ((exponent + 112) << 23) | (mantissa << 13);
    float value;
    std::memcpy(&value, &floatBits, sizeof value);
    return value;
}

/// floatFromHalf of every binary16 pattern (256 KB, built at first use), for the default path's triangular solves,
/// which read one half per value of the factor: a lookup costs less than the bit arithmetic, with the same floats.
inline const float* halfFloats()
{
    static const std::vector<float> table = []
    {
        std::vector<float> floats(std::size_t(1) << 16);
        for (std::size_t bits = 0; bits < floats.size(); ++bits)
        {
            floats[bits] = floatFromHalf(std::uint16_t(bits));
        }
        return floats;
    }();
    return table.data();
}

#if defined(__x86_64__) && defined(__GNUC__)
/// halfFromReal of eight floats at once with F16C's conversion, which rounds to the nearest half, ties to even, as
/// halfFromReal does: the magnitudes past 65504 are clamped to it first, as halfFromReal clamps them (IEEE would give
/// infinity from 65520 up). A NaN is not a value a factor holds: its lane is left to the caller (halfFromReal gives
/// 0x7BFF with its sign).
[[gnu::always_inline]] inline __attribute__((target("avx2,f16c"))) __m128i halvesFromFloatsF16c(__m256 values)
{
    const __m256 largest = _mm256_set1_ps(65504.0f);
    const __m256 clamped = _mm256_min_ps(_mm256_max_ps(values, _mm256_sub_ps(_mm256_setzero_ps(), largest)), largest);
    return _mm256_cvtps_ph(clamped, _MM_FROUND_TO_NEAREST_INT | _MM_FROUND_NO_EXC);
}
#endif
} // namespace masse
