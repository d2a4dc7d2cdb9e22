#include "core/StateHash.h"

#include <cstring>

namespace masse
{
namespace
{
constexpr std::uint64_t fnvOffset = 14695981039346656037ull;
constexpr std::uint64_t fnvPrime = 1099511628211ull;

std::uint64_t mix(std::uint64_t hash, const std::vector<Vec3>& values)
{
    for (const Vec3& value : values)
    {
        unsigned char bytes[sizeof(Real) * 3];
        std::memcpy(bytes, value.data(), sizeof(bytes));
        for (unsigned char byte : bytes)
        {
            hash = (hash ^ byte) * fnvPrime;
        }
    }
    return hash;
}
} // namespace

std::uint64_t stateHash(const Particles& particles)
{
    return mix(mix(fnvOffset, particles.position), particles.velocity);
}
} // namespace masse
