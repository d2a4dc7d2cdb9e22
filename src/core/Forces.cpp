#include "Forces.h"

#include "SpringForce.h"

#include <algorithm>
#include <cmath>

namespace masse
{
namespace
{
/// Springs handled per block; the block's scratch arrays (about 5 KB) stay in L1.
constexpr std::size_t springBlock = 128;

/// The hot loop, in blocks of three passes: gather each spring's extension vector and relative velocity; compute
/// the force magnitudes (a loop without indirection, which the compiler vectorises, so square roots and divisions go
/// two at a time); scatter the forces. Restrict pointers tell the compiler the force array aliases no input. The
/// repulsion is a template switch so the usual sheet, without it, pays nothing for it.
template <bool withRepulsion>
void springLoop(const SpringSet& springs, Real repulsion, const Vec3* __restrict x, const Vec3* __restrict v,
                Vec3* __restrict force)
{
    const std::size_t count = springs.size();
    const SpringEnds* __restrict ends = springs.ends.data();
    Vec3 d[springBlock];
    Real lengthSquared[springBlock];
    Real speedTimesLength[springBlock]; // (v_a - v_b) . d
    Real scale[springBlock];            // force magnitude along n, divided by |d|
    for (std::size_t start = 0; start < count; start += springBlock)
    {
        const std::size_t n = std::min(springBlock, count - start);
        const SpringEnds* __restrict blockEnds = ends + start;
        for (std::size_t j = 0; j < n; ++j)
        {
            const Index a = blockEnds[j].a;
            const Index b = blockEnds[j].b;
            d[j] = x[a] - x[b];
            lengthSquared[j] = d[j].squaredNorm();
            speedTimesLength[j] = (v[a] - v[b]).dot(d[j]);
        }
        const Real* __restrict rest = springs.restLength.data() + start;
        const Real* __restrict stiffness = springs.stiffness.data() + start;
        const Real* __restrict damping = springs.damping.data() + start;
        for (std::size_t j = 0; j < n; ++j)
        {
            const Real length = std::sqrt(lengthSquared[j]);
            const Real inverse = Real(1) / length;
            Real magnitude = hookeMagnitude(length, speedTimesLength[j] * inverse, stiffness[j], damping[j], rest[j]);
            if constexpr (withRepulsion)
            {
                magnitude += repulsionMagnitude(length, rest[j], repulsion);
            }
            // A spring squeezed to a point has no direction: it exerts nothing rather than a NaN.
            scale[j] = length > degenerateLengthFraction * rest[j] ? magnitude * inverse : Real(0);
        }
        for (std::size_t j = 0; j < n; ++j)
        {
            const Vec3 f = scale[j] * d[j];
            force[blockEnds[j].a] += f;
            force[blockEnds[j].b] -= f;
        }
    }
}
} // namespace

void accumulateSpringForces(const SpringSet& springs, Real repulsion, const std::vector<Vec3>& x,
                            const std::vector<Vec3>& v, std::vector<Vec3>& force)
{
    if (repulsion > 0)
    {
        springLoop<true>(springs, repulsion, x.data(), v.data(), force.data());
    }
    else
    {
        springLoop<false>(springs, repulsion, x.data(), v.data(), force.data());
    }
}

void evaluateForces(const MassSpringSystem& system, const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                    std::vector<Vec3>& force)
{
    const Particles& p = system.particles;
    const std::size_t n = p.size();
    force.resize(n);
    const Vec3 gravity = system.forces.gravity;
    const Real drag = system.forces.airDamping;
    for (std::size_t i = 0; i < n; ++i)
    {
        force[i] = p.mass[i] * (gravity - drag * v[i]) + p.externalForce[i];
    }
    accumulateSpringForces(system.springs, system.forces.repulsion, x, v, force);
    for (const UserSpring& spring : system.userSprings.all())
    {
        force[spring.mass] += evaluateUserSpring(spring, x[spring.mass], v[spring.mass]).force;
    }
}
} // namespace masse
