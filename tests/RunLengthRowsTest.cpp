#include "core/RunLengthRows.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>

namespace masse
{
namespace
{
/// GCC's own conversion, correctly rounded from double (ties to even): the reference.
std::uint16_t referenceHalf(double value)
{
    const _Float16 half = _Float16(value);
    std::uint16_t bits;
    std::memcpy(&bits, &half, sizeof bits);
    return bits;
}

double halfValue(std::uint16_t bits)
{
    _Float16 half;
    std::memcpy(&half, &bits, sizeof half);
    return double(half);
}

bool finiteHalf(std::uint16_t bits)
{
    return ((bits >> 10) & 0x1F) != 0x1F;
}
} // namespace

// The factor's values are rounded to half precision in software (halfFromReal), so that the bits do not depend on the
// processor. Its rounding must be IEEE's to nearest, ties to even, straight from double: it is compared with GCC's
// _Float16 conversion on every finite half, on the midpoint between each pair of neighbours (a tie, where the even one
// wins) and just either side of it (where the nearest wins), and on a million random doubles spread over the halves'
// range, subnormals included. Past the largest finite half, where IEEE gives infinity, it clamps to 65504 instead.
// floatFromHalf reads every finite half back exactly.
TEST(RunLengthRows, HalfRoundingIsIeeeNearestEvenAndClampsInsteadOfOverflowing)
{
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
} // namespace masse
