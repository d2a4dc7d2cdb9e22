#include "core/linear/Half.h"

#include "core/forces/SimdPath.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <random>
#include <vector>

namespace masse
{
namespace
{
/// The value of the finite half `bits`, from IEEE binary16's definition (independent of floatFromHalf).
double halfValue(std::uint16_t bits)
{
    const int exponent = (bits >> 10) & 0x1F;
    const int mantissa = bits & 0x3FF;
    const double magnitude =
        exponent == 0 ? std::ldexp(double(mantissa), -24) : std::ldexp(double(1024 + mantissa), exponent - 25);
    return (bits & 0x8000) ? -magnitude : magnitude;
}

bool finiteHalf(std::uint16_t bits)
{
    return ((bits >> 10) & 0x1F) != 0x1F;
}

/// IEEE's rounding to the nearest half, ties to even, by search (the reference; 0x7C00 past the largest finite half,
/// where IEEE rounds to infinity). The differences below are exact: the neighbours are within a factor of two of the
/// value, or zero.
std::uint16_t referenceHalf(double value)
{
    const double magnitude = std::abs(value);
    const auto sign = std::uint16_t(std::signbit(value) ? 0x8000 : 0);
    if (magnitude >= 65520.0)
    {
        return std::uint16_t(sign | 0x7C00);
    }
    std::uint16_t below = 0; // the largest half <= magnitude
    std::uint16_t step = 0x4000;
    while (step > 0)
    {
        const auto candidate = std::uint16_t(below + step);
        if (candidate <= 0x7BFF && halfValue(candidate) <= magnitude)
        {
            below = candidate;
        }
        step = std::uint16_t(step / 2);
    }
    if (below == 0x7BFF)
    {
        return std::uint16_t(sign | below); // between 65504 and 65520: down
    }
    const auto above = std::uint16_t(below + 1);
    const double down = magnitude - halfValue(below);
    const double up = halfValue(above) - magnitude;
    const bool toAbove = up < down || (up == down && (above & 1) == 0);
    return std::uint16_t(sign | (toAbove ? above : below));
}
} // namespace

// The factor's values are rounded to half precision in software (halfFromReal), so that the bits do not depend on the
// processor. Its rounding must be IEEE's to nearest, ties to even, straight from double: it is compared with a rounding
// by search over the halves' values (referenceHalf; clang 14 has no _Float16 on x86) on every finite half, on the
// midpoint between each pair of neighbours (a tie, where the even one wins) and just either side of it (where the
// nearest wins), and on a million random doubles spread over the halves' range, subnormals included. Past the largest
// finite half, where IEEE gives infinity, it clamps to 65504 instead. floatFromHalf reads every finite half back
// exactly, and halfFloats (the default path's table) holds its float for every pattern, bit for bit.
TEST(Half, RoundingIsIeeeNearestEvenAndClampsInsteadOfOverflowing)
{
    for (std::uint32_t bits = 0; bits < 0x10000; ++bits)
    {
        const float fromTable = halfFloats()[bits];
        const float computed = floatFromHalf(std::uint16_t(bits));
        ASSERT_EQ(std::memcmp(&fromTable, &computed, sizeof(float)), 0) << "bits " << bits;
    }
    for (std::uint32_t bits = 0; bits < 0x10000; ++bits)
    {
        const auto half = std::uint16_t(bits);
        if (!finiteHalf(half))
        {
            continue;
        }
        const double value = halfValue(half);
        ASSERT_EQ(double(floatFromHalf(half)), value) << "bits " << bits;
        ASSERT_EQ(halfFromReal(value), half) << "bits " << bits;
        const auto next = std::uint16_t(bits + 1);
        if ((bits & 0x7FFF) == 0x7BFF || !finiteHalf(next) || (bits & 0x8000) != (next & 0x8000))
        {
            continue;
        }
        const double midpoint = (value + halfValue(next)) / 2; // exact: a half has 11 bits
        for (const double probe : {midpoint, std::nextafter(midpoint, 0.0), std::nextafter(midpoint, 2 * midpoint)})
        {
            ASSERT_EQ(halfFromReal(probe), referenceHalf(probe)) << "between bits " << bits << " and the next";
        }
    }
    std::mt19937_64 random(7);
    std::uniform_real_distribution<double> exponent(-30.0, 16.0);
    std::uniform_int_distribution<int> sign(0, 1);
    for (int k = 0; k < 1000000; ++k)
    {
        const double value = (sign(random) ? -1.0 : 1.0) * std::exp2(exponent(random));
        if (std::abs(value) >= 65520.0)
        {
            ASSERT_EQ(halfFromReal(value) & 0x7FFF, 0x7BFF) << value;
            continue;
        }
        ASSERT_EQ(halfFromReal(value), referenceHalf(value)) << value;
    }
    EXPECT_EQ(halfFromReal(0.0), 0x0000);
    EXPECT_EQ(halfFromReal(-0.0), 0x8000);
    EXPECT_EQ(halfFromReal(65519.99), 0x7BFF); // IEEE rounds this down to 65504 as well
    EXPECT_EQ(referenceHalf(65520.0), 0x7C00); // ... and this up to infinity, which a factor must not hold
    EXPECT_EQ(halfFromReal(65520.0), 0x7BFF);
    EXPECT_EQ(halfFromReal(-1e300), 0xFBFF);
    EXPECT_EQ(halfFromReal(1e-300), 0x0000);
}

#if defined(__x86_64__) && defined(__GNUC__)
namespace
{
/// halvesFromFloatsF16c of eight floats, compiled for F16C (it is inlined into its caller, which must be).
__attribute__((target("avx2,f16c"))) void halvesF16c(const float* values, std::uint16_t* halves)
{
    _mm_storeu_si128(reinterpret_cast<__m128i*>(halves), halvesFromFloatsF16c(_mm256_loadu_ps(values)));
}
} // namespace

// The AVX2 and AVX-512 paths round the factor's single-precision values to half with F16C's conversion
// (halvesFromFloatsF16c), the default path with halfFromReal: both give the same halves for every finite float and
// the infinities, checked on every float whose bits are a multiple of 251 (17 million, every exponent and sign) and on
// every float within four steps of each half and of each midpoint between neighbouring halves (ties and the values
// either side of them), subnormal halves and the clamp at 65504 included.
TEST(Half, F16cConversionGivesHalfFromRealsHalves)
{
    if (!simdPathSupported(SimdPath::Avx2))
    {
        // Skipped without AVX2 (whose processors all have F16C): the software rounding above is then the only one.
        GTEST_SKIP() << "this processor has no F16C: there is no hardware conversion to compare";
    }
    std::vector<float> values;
    for (std::uint64_t bits = 0; bits <= 0xFFFFFFFFull; bits += 251)
    {
        const auto word = std::uint32_t(bits);
        float value;
        std::memcpy(&value, &word, sizeof value);
        if (!std::isnan(value))
        {
            values.push_back(value);
        }
    }
    for (std::uint32_t bits = 0; bits < 0x7C00; ++bits)
    {
        const double value = halfValue(std::uint16_t(bits));
        const double midpoint = (value + halfValue(std::uint16_t(bits + 1))) / 2;
        for (const double centre : {value, midpoint})
        {
            float probe = float(centre); // exact: a half and a midpoint have at most 12 bits
            for (int step = 0; step < 4; ++step)
            {
                probe = std::nextafter(probe, -1.0f);
            }
            for (int step = 0; step < 9; ++step)
            {
                values.push_back(probe);
                values.push_back(-probe);
                probe = std::nextafter(probe, 2.0f * float(centre) + 1.0f);
            }
        }
    }
    values.push_back(std::numeric_limits<float>::infinity());
    values.push_back(-std::numeric_limits<float>::infinity());
    values.push_back(65520.0f);
    values.push_back(1e38f);
    while (values.size() % 8 != 0)
    {
        values.push_back(0.0f);
    }
    std::vector<std::uint16_t> halves(values.size());
    for (std::size_t k = 0; k < values.size(); k += 8)
    {
        halvesF16c(values.data() + k, halves.data() + k);
    }
    for (std::size_t k = 0; k < values.size(); ++k)
    {
        ASSERT_EQ(halves[k], halfFromReal(double(values[k]))) << values[k];
    }
}
#endif
} // namespace masse
