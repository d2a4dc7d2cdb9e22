#include "core/forces/Forces.h"

#include "core/forces/BandedForces.h"
#include "core/forces/SimdPath.h"
#include "core/forces/SpringForce.h"
#include "core/parallel/TaskPool.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>

namespace masse
{
namespace
{
/// Springs handled per block; the block's scratch arrays (about 4 KB) stay in L1.
constexpr std::size_t springBlock = 128;
/// Springs per parallel chunk: large enough that waking a thread pays.
constexpr std::size_t springChunk = 16384;

/// Pass 1 over springs [begin, end): each spring's force magnitude along d = x_a - x_b, divided by |d| (so the
/// force on a is scale * d). Blocks of two loops: gather each spring's extension and relative velocity; compute the
/// magnitudes (a loop without indirection, which the compiler vectorises, so square roots and divisions go two or
/// more at a time). The repulsion is a template switch so the usual sheet, without it, pays nothing for it. Writes
/// only scale[begin, end): no two chunks share an output. Inlined into one function per SIMD path (below).
template <bool withRepulsion>
[[gnu::always_inline]] inline void springScalesBody(const SpringSet& springs, Real repulsion, const Vec3* __restrict x,
                                                    const Vec3* __restrict v, std::size_t begin, std::size_t end,
                                                    Real* __restrict scale)
{
    const SpringEnds* __restrict ends = springs.ends().data();
    Real lengthSquared[springBlock];
    Real speedTimesLength[springBlock]; // (v_a - v_b) . d
    for (std::size_t start = begin; start < end; start += springBlock)
    {
        const std::size_t n = std::min(springBlock, end - start);
        const SpringEnds* __restrict blockEnds = ends + start;
        for (std::size_t j = 0; j < n; ++j)
        {
            const Index a = blockEnds[j].a;
            const Index b = blockEnds[j].b;
            const Vec3 d = x[a] - x[b];
            lengthSquared[j] = d.squaredNorm();
            speedTimesLength[j] = (v[a] - v[b]).dot(d);
        }
        const Real* __restrict rest = springs.restLength().data() + start;
        const Real* __restrict stiffness = springs.stiffness().data() + start;
        const Real* __restrict damping = springs.damping().data() + start;
        Real* __restrict blockScale = scale + start;
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
            blockScale[j] = length > degenerateLengthFraction * rest[j] ? magnitude * inverse : Real(0);
        }
    }
}

/// What pass 2 reads and writes.
struct GatherArgs
{
    const SpringAdjacency* adjacency;
    const Real* scale;
    const Vec3* x;
    const Vec3* v;
    const Real* mass;
    const Vec3* externalForce;
    Vec3 gravity;
    Real drag;
    Vec3* force;
    // The symplectic kick (gatherBody with `kick`): v_i += (h / m_i) f_i as soon as f_i is known.
    Real h = 0;
    const Real* inverseMass = nullptr;
    Vec3* velocity = nullptr;
};

/// Pass 2 over masses [begin, end): each mass's force, its own (gravity, drag, external; or, without `ownForces`, the
/// force already there) plus its springs' in increasing spring index. The force on mass i of a spring to `other` is
/// scale * (x_i - x_other): +scale d at end a, and exactly -scale d at end b (IEEE negation is exact), so the sum has
/// the bits of the serial scatter force[a] += f, force[b] -= f. With `kick`, the mass's velocity takes its symplectic
/// update from the force just summed, while its line is in cache: the pass reads no other mass's velocity, so the
/// update cannot be seen by another mass's force.
template <bool ownForces, bool kick = false>
[[gnu::always_inline]] inline void gatherBody(const GatherArgs& args, std::size_t begin, std::size_t end)
{
    const std::size_t* __restrict offsets = args.adjacency->offsets.data();
    const SpringAdjacency::Entry* __restrict entry = args.adjacency->entries.data();
    const Real* __restrict scale = args.scale;
    const Vec3* __restrict x = args.x;
    for (std::size_t i = begin; i < end; ++i)
    {
        Vec3 f = ownForces ? Vec3(args.mass[i] * (args.gravity - args.drag * args.v[i]) + args.externalForce[i])
                           : args.force[i];
        const Vec3 xi = x[i];
        for (std::size_t k = offsets[i]; k < offsets[i + 1]; ++k)
        {
            f += scale[entry[k].spring] * (xi - x[entry[k].other]);
        }
        args.force[i] = f;
        if constexpr (kick)
        {
            args.velocity[i] += (args.h * args.inverseMass[i]) * f;
        }
    }
}

// One copy of each kernel per SIMD path. Only the instruction set differs; see SimdPath.h for why the bits do not.
#define MASSE_FORCE_KERNELS(suffix, targetAttribute)                                                                   \
    template <bool withRepulsion>                                                                                      \
    targetAttribute void springScales##suffix(const SpringSet& springs, Real repulsion, const Vec3* x, const Vec3* v,  \
                                              std::size_t begin, std::size_t end, Real* scale)                         \
    {                                                                                                                  \
        springScalesBody<withRepulsion>(springs, repulsion, x, v, begin, end, scale);                                  \
    }                                                                                                                  \
    template <bool ownForces>                                                                                          \
    targetAttribute void gather##suffix(const GatherArgs& args, std::size_t begin, std::size_t end)                    \
    {                                                                                                                  \
        gatherBody<ownForces>(args, begin, end);                                                                       \
    }                                                                                                                  \
    targetAttribute void gatherAndKick##suffix(const GatherArgs& args, std::size_t begin, std::size_t end)             \
    {                                                                                                                  \
        gatherBody<true, true>(args, begin, end);                                                                      \
    }

MASSE_FORCE_KERNELS(Default, )
#if defined(__x86_64__) && defined(__GNUC__)
MASSE_FORCE_KERNELS(Avx2, __attribute__((target("avx2"))))
MASSE_FORCE_KERNELS(Avx512, __attribute__((target("avx512f"))))
#endif
#undef MASSE_FORCE_KERNELS

template <bool withRepulsion>
void springScalesOn(SimdPath path, const SpringSet& springs, Real repulsion, const Vec3* x, const Vec3* v,
                    std::size_t begin, std::size_t end, Real* scale)
{
    switch (path)
    {
#if defined(__x86_64__) && defined(__GNUC__)
    case SimdPath::Avx512:
        return springScalesAvx512<withRepulsion>(springs, repulsion, x, v, begin, end, scale);
    case SimdPath::Avx2:
        return springScalesAvx2<withRepulsion>(springs, repulsion, x, v, begin, end, scale);
#endif
    default:
        return springScalesDefault<withRepulsion>(springs, repulsion, x, v, begin, end, scale);
    }
}

template <bool ownForces> void gatherOn(SimdPath path, const GatherArgs& args, std::size_t begin, std::size_t end)
{
    switch (path)
    {
#if defined(__x86_64__) && defined(__GNUC__)
    case SimdPath::Avx512:
        return gatherAvx512<ownForces>(args, begin, end);
    case SimdPath::Avx2:
        return gatherAvx2<ownForces>(args, begin, end);
#endif
    default:
        return gatherDefault<ownForces>(args, begin, end);
    }
}

void gatherAndKickOn(SimdPath path, const GatherArgs& args, std::size_t begin, std::size_t end)
{
    switch (path)
    {
#if defined(__x86_64__) && defined(__GNUC__)
    case SimdPath::Avx512:
        return gatherAndKickAvx512(args, begin, end);
    case SimdPath::Avx2:
        return gatherAndKickAvx2(args, begin, end);
#endif
    default:
        return gatherAndKickDefault(args, begin, end);
    }
}

/// The banded kernel's arguments for a system's total forces at x, v.
BandedForceArgs bandedArgs(const MassSpringSystem& system, const SpringRowPlan& plan, const std::vector<Vec3>& x,
                           const std::vector<Vec3>& v, std::vector<Vec3>& force)
{
    BandedForceArgs args;
    args.plan = &plan;
    args.springs = &system.springs;
    args.repulsion = system.forces.repulsion;
    args.x = x.data();
    args.v = v.data();
    args.force = force.data();
    args.mass = system.particles.mass.data();
    args.externalForce = system.particles.externalForce.data();
    args.gravity = system.forces.gravity;
    args.drag = system.forces.airDamping;
    return args;
}

/// Pass 1 over every spring, in parallel chunks.
void computeSpringScales(const SpringSet& springs, Real repulsion, const std::vector<Vec3>& x,
                         const std::vector<Vec3>& v, std::vector<Real>& scale)
{
    scale.resize(springs.size());
    const SimdPath path = activeSimdPath();
    parallelFor(springs.size(), springChunk,
                [&](std::size_t begin, std::size_t end)
                {
                    if (repulsion > 0)
                    {
                        springScalesOn<true>(path, springs, repulsion, x.data(), v.data(), begin, end, scale.data());
                    }
                    else
                    {
                        springScalesOn<false>(path, springs, repulsion, x.data(), v.data(), begin, end, scale.data());
                    }
                });
}

/// The per-spring scales of the calling thread's last evaluation (kept to save an allocation per substep).
thread_local std::vector<Real> springScaleScratch;
} // namespace

void accumulateSpringForces(const SpringSet& springs, Real repulsion, const std::vector<Vec3>& x,
                            const std::vector<Vec3>& v, std::vector<Vec3>& force)
{
    if (const SpringRowPlan* plan = springs.rowPlan(x.size()))
    {
        BandedForceArgs args;
        args.plan = plan;
        args.springs = &springs;
        args.repulsion = repulsion;
        args.x = x.data();
        args.v = v.data();
        args.force = force.data();
        runBandedForces(BandedPass::AddSpringForces, args);
        return;
    }
    std::vector<Real>& scale = springScaleScratch;
    computeSpringScales(springs, repulsion, x, v, scale);
    GatherArgs args{&springs.adjacency(x.size()),
                    scale.data(),
                    x.data(),
                    v.data(),
                    nullptr,
                    nullptr,
                    Vec3::Zero(),
                    0,
                    force.data()};
    const SimdPath path = activeSimdPath();
    parallelFor(x.size(), massChunkSize,
                [&](std::size_t begin, std::size_t end) { gatherOn<false>(path, args, begin, end); });
}

void evaluateForces(const MassSpringSystem& system, const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                    std::vector<Vec3>& force)
{
    const Particles& p = system.particles;
    const std::size_t n = p.size();
    force.resize(n);
    if (const SpringRowPlan* plan = system.springs.rowPlan(n))
    {
        BandedForceArgs args = bandedArgs(system, *plan, x, v, force);
        runBandedForces(BandedPass::TotalForces, args);
    }
    else
    {
        std::vector<Real>& scale = springScaleScratch;
        computeSpringScales(system.springs, system.forces.repulsion, x, v, scale);
        GatherArgs args{&system.springs.adjacency(n),
                        scale.data(),
                        x.data(),
                        v.data(),
                        p.mass.data(),
                        p.externalForce.data(),
                        system.forces.gravity,
                        system.forces.airDamping,
                        force.data()};
        const SimdPath path = activeSimdPath();
        parallelFor(n, massChunkSize,
                    [&](std::size_t begin, std::size_t end) { gatherOn<true>(path, args, begin, end); });
    }
    for (const UserSpring& spring : system.userSprings.all())
    {
        force[spring.mass] += evaluateUserSpring(spring, x[spring.mass], v[spring.mass]).force;
    }
}

bool noExternalForces(const Particles& particles)
{
    // Bit patterns, not values: -0 == 0, but adding -0 keeps a -0 sum where adding +0 makes it +0.
    static_assert(sizeof(Real) == sizeof(std::uint64_t));
    const Real* components = particles.externalForce.empty() ? nullptr : particles.externalForce[0].data();
    const std::size_t count = 3 * particles.externalForce.size();
    for (std::size_t k = 0; k < count; ++k)
    {
        if (std::bit_cast<std::uint64_t>(components[k]) != 0)
        {
            return false;
        }
    }
    return true;
}

bool symplecticSubstep(MassSpringSystem& system, Real h, bool externalForces, bool storeForces)
{
    if (!system.userSprings.all().empty())
    {
        return false; // their forces come after the gather, and the kick must see them in the same sum
    }
    Particles& p = system.particles;
    const std::size_t n = p.size();
    p.force.resize(n);
    if (const SpringRowPlan* plan = system.springs.rowPlan(n))
    {
        BandedForceArgs args = bandedArgs(system, *plan, p.position, p.velocity, p.force);
        args.h = h;
        args.inverseMass = p.inverseMass.data();
        args.position = p.position.data();
        args.velocity = p.velocity.data();
        if (!storeForces)
        {
            args.force = nullptr;
        }
        runBandedForces(
            externalForces ? BandedPass::SymplecticSubstep : BandedPass::SymplecticSubstepWithoutExternalForces, args);
        return true;
    }
    std::vector<Real>& scale = springScaleScratch;
    computeSpringScales(system.springs, system.forces.repulsion, p.position, p.velocity, scale);
    GatherArgs args{
        &system.springs.adjacency(n), scale.data(),          p.position.data(),        p.velocity.data(), p.mass.data(),
        p.externalForce.data(),       system.forces.gravity, system.forces.airDamping, p.force.data()};
    args.h = h;
    args.inverseMass = p.inverseMass.data();
    args.velocity = p.velocity.data();
    const SimdPath path = activeSimdPath();
    parallelFor(n, massChunkSize, [&](std::size_t begin, std::size_t end) { gatherAndKickOn(path, args, begin, end); });
    // The velocities are updated: move the positions (a pass of its own, as no mass's force may see a moved mass).
    parallelFor(n, massChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    for (std::size_t i = begin; i < end; ++i)
                    {
                        p.position[i] += h * p.velocity[i];
                    }
                });
    return true;
}
} // namespace masse
