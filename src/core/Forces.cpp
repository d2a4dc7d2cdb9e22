#include "Forces.h"

#include "SimdPath.h"
#include "SpringForce.h"
#include "TaskPool.h"

#include <algorithm>
#include <cmath>

namespace masse
{
namespace
{
/// Masses per block of a chunk: a block's force accumulators stay in L1 while each rank's runs are added to them.
constexpr std::size_t massBlock = 512;
/// Springs per parallel chunk of the first pass: large enough that waking a thread pays.
constexpr std::size_t springChunk = 16384;

/// Pass 1 over one spring run: spring t joins the mass at (xa[t], ya[t], za[t]) with velocity (vxa[t] ...) to the mass
/// at (xb[t] ...). Writes scale[t], the spring's force magnitude on a along d = x_a - x_b divided by |d|, so the force
/// on a is scale d and on b exactly -scale d. One loop without indirection, which the compiler vectorises: square roots
/// and divisions go a vector at a time. The pointers are parameters because GCC honours __restrict only there. The
/// repulsion is a template switch so the usual sheet, without it, pays nothing for it.
template <bool withRepulsion>
[[gnu::always_inline]] inline void springScalesBody(std::size_t count, std::size_t stride, const Real* __restrict xa,
                                                    const Real* __restrict xb, const Real* __restrict va,
                                                    const Real* __restrict vb, const Real* __restrict rest,
                                                    const Real* __restrict stiffness, const Real* __restrict damping,
                                                    Real repulsion, Real* __restrict scale)
{
    for (std::size_t t = 0; t < count; ++t)
    {
        const Real dx = xa[t] - xb[t];
        const Real dy = xa[t + stride] - xb[t + stride];
        const Real dz = xa[t + 2 * stride] - xb[t + 2 * stride];
        const Real lengthSquared = dx * dx + dy * dy + dz * dz;
        const Real speedTimesLength = (va[t] - vb[t]) * dx + (va[t + stride] - vb[t + stride]) * dy +
                                      (va[t + 2 * stride] - vb[t + 2 * stride]) * dz;
        const Real length = std::sqrt(lengthSquared);
        const Real inverse = Real(1) / length;
        Real magnitude = hookeMagnitude(length, speedTimesLength * inverse, stiffness[t], damping[t], rest[t]);
        if constexpr (withRepulsion)
        {
            magnitude += repulsionMagnitude(length, rest[t], repulsion);
        }
        // A spring squeezed to a point has no direction: it exerts nothing rather than a NaN.
        scale[t] = length > degenerateLengthFraction * rest[t] ? magnitude * inverse : Real(0);
    }
}

/// Pass 2 over one mass run: mass t, at (xi[t] ...), adds the force scale[t] (x_i - x_other) of its spring to the
/// mass at (xo[t] ...): +scale d at the spring's end a, and exactly -scale d at its end b.
[[gnu::always_inline]] inline void gatherRunBody(std::size_t count, std::size_t stride, const Real* __restrict xi,
                                                 const Real* __restrict xo, const Real* __restrict scale,
                                                 Real* __restrict f)
{
    for (std::size_t t = 0; t < count; ++t)
    {
        f[t] += scale[t] * (xi[t] - xo[t]);
        f[t + stride] += scale[t] * (xi[t + stride] - xo[t + stride]);
        f[t + 2 * stride] += scale[t] * (xi[t + 2 * stride] - xo[t + 2 * stride]);
    }
}

#define MASSE_SCALES_PARAMETERS                                                                                        \
    std::size_t count, std::size_t stride, const Real *__restrict xa, const Real *__restrict xb,                       \
        const Real *__restrict va, const Real *__restrict vb, const Real *__restrict rest,                             \
        const Real *__restrict stiffness, const Real *__restrict damping, Real repulsion, Real *__restrict scale
#define MASSE_SCALES_ARGUMENTS count, stride, xa, xb, va, vb, rest, stiffness, damping, repulsion, scale
#define MASSE_GATHER_PARAMETERS                                                                                        \
    std::size_t count, std::size_t stride, const Real *__restrict xi, const Real *__restrict xo,                       \
        const Real *__restrict scale, Real *__restrict f
#define MASSE_GATHER_ARGUMENTS count, stride, xi, xo, scale, f

// One copy of each kernel per SIMD path. Only the instruction set differs; see SimdPath.h for why the bits do not.
#define MASSE_FORCE_KERNELS(suffix, targetAttribute)                                                                  \
    template <bool withRepulsion>                                                                                      \
    targetAttribute void springScales##suffix(MASSE_SCALES_PARAMETERS)                                                 \
    {                                                                                                                  \
        springScalesBody<withRepulsion>(MASSE_SCALES_ARGUMENTS);                                                       \
    }                                                                                                                  \
    targetAttribute void gatherRun##suffix(MASSE_GATHER_PARAMETERS)                                                    \
    {                                                                                                                  \
        gatherRunBody(MASSE_GATHER_ARGUMENTS);                                                                         \
    }

MASSE_FORCE_KERNELS(Default, )
#if defined(__x86_64__) && defined(__GNUC__)
MASSE_FORCE_KERNELS(Avx2, __attribute__((target("avx2"))))
MASSE_FORCE_KERNELS(Avx512, __attribute__((target("avx512f"))))
#endif
#undef MASSE_FORCE_KERNELS

using ScalesKernel = void (*)(MASSE_SCALES_PARAMETERS);
using GatherKernel = void (*)(MASSE_GATHER_PARAMETERS);
#undef MASSE_SCALES_PARAMETERS
#undef MASSE_SCALES_ARGUMENTS
#undef MASSE_GATHER_PARAMETERS
#undef MASSE_GATHER_ARGUMENTS

template <bool withRepulsion>
ScalesKernel scalesKernelFor(SimdPath path)
{
    switch (path)
    {
#if defined(__x86_64__) && defined(__GNUC__)
    case SimdPath::Avx512:
        return &springScalesAvx512<withRepulsion>;
    case SimdPath::Avx2:
        return &springScalesAvx2<withRepulsion>;
#endif
    default:
        return &springScalesDefault<withRepulsion>;
    }
}

GatherKernel gatherKernelFor(SimdPath path)
{
    switch (path)
    {
#if defined(__x86_64__) && defined(__GNUC__)
    case SimdPath::Avx512:
        return &gatherRunAvx512;
    case SimdPath::Avx2:
        return &gatherRunAvx2;
#endif
    default:
        return &gatherRunDefault;
    }
}

/// The state the spring kernels read and write as structures of arrays, so that a run's loop loads consecutive
/// doubles: each of x, v and force holds all masses' x coordinates, then all y, then all z (`stride` apart).
struct SpringKernelArgs
{
    const SpringRuns* runs;
    std::size_t stride;
    const Real* x;
    const Real* v;
    const Real* rest;
    const Real* stiffness;
    const Real* damping;
    Real repulsion;
    Real* scale;
    Real* force;
};

/// Pass 1 over springs [begin, end): the parts of the spring runs inside the range. Writes only scale[begin, end).
void computeSpringScales(ScalesKernel kernel, const SpringKernelArgs& a, std::size_t begin, std::size_t end)
{
    const std::vector<SpringRun>& runs = a.runs->springRuns;
    auto run = std::partition_point(runs.begin(), runs.end(), [&](const SpringRun& r) {
        return std::size_t(r.firstSpring) + r.count <= begin;
    });
    for (; run != runs.end() && std::size_t(run->firstSpring) < end; ++run)
    {
        const std::size_t s = std::max(begin, std::size_t(run->firstSpring));
        const std::size_t stop = std::min(end, std::size_t(run->firstSpring) + run->count);
        const std::size_t i = std::size_t(run->firstMass) + (s - run->firstSpring);
        const std::size_t o = std::size_t(std::int64_t(i) + run->otherOffset);
        kernel(stop - s, a.stride, a.x + i, a.x + o, a.v + i, a.v + o, a.rest + s, a.stiffness + s, a.damping + s,
               a.repulsion, a.scale + s);
    }
}

/// Pass 2 over masses [begin, end): block by block, rank by rank, the part of each mass run inside the block is added
/// to the accumulators. A mass sums its springs in rank order whatever block or thread holds it.
void gatherSpringForces(GatherKernel kernel, const SpringKernelArgs& a, std::size_t begin, std::size_t end)
{
    const SpringRuns& runs = *a.runs;
    for (std::size_t blockBegin = begin; blockBegin < end; blockBegin += massBlock)
    {
        const std::size_t blockEnd = std::min(end, blockBegin + massBlock);
        for (std::size_t rank = 0; rank < runs.rankCount(); ++rank)
        {
            const SpringRun* run = runs.runs.data() + runs.rankStart[rank];
            const SpringRun* last = runs.runs.data() + runs.rankStart[rank + 1];
            run = std::partition_point(run, last, [&](const SpringRun& r) {
                return std::size_t(r.firstMass) + r.count <= blockBegin;
            });
            for (; run != last && std::size_t(run->firstMass) < blockEnd; ++run)
            {
                const std::size_t i = std::max(blockBegin, std::size_t(run->firstMass));
                const std::size_t stop = std::min(blockEnd, std::size_t(run->firstMass) + run->count);
                const std::size_t o = std::size_t(std::int64_t(i) + run->otherOffset);
                const std::size_t s = std::size_t(run->firstSpring) + (i - run->firstMass);
                kernel(stop - i, a.stride, a.x + i, a.x + o, a.scale + s, a.force + i);
            }
        }
    }
}

/// The calling thread's structure-of-arrays copies (kept to save allocations per substep): 6 state arrays, 3 force
/// accumulators and the springs' scales.
thread_local std::vector<Real> springScratch;

/// The force on every mass: its own force (`ownForce(i)`, a Vec3) plus its springs', written to `force`.
template <typename OwnForce>
void springForcesInto(const SpringSet& springs, Real repulsion, const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                      std::vector<Vec3>& force, const OwnForce& ownForce)
{
    const std::size_t n = x.size();
    const std::size_t m = springs.size();
    std::vector<Real>& scratch = springScratch;
    scratch.resize(9 * n + m);
    Real* const px = scratch.data();
    Real* const pv = px + 3 * n;
    Real* const pf = px + 6 * n;
    const SpringKernelArgs args{&springs.runs(n),          n,         px,           pv, springs.restLength.data(),
                                springs.stiffness.data(),   springs.damping.data(), repulsion, px + 9 * n, pf};
    parallelFor(n, massChunkSize, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i)
        {
            const Vec3 own = ownForce(i);
            for (int c = 0; c < 3; ++c)
            {
                px[i + std::size_t(c) * n] = x[i][c];
                pv[i + std::size_t(c) * n] = v[i][c];
                pf[i + std::size_t(c) * n] = own[c];
            }
        }
    });
    const SimdPath path = activeSimdPath();
    const ScalesKernel scales = repulsion > 0 ? scalesKernelFor<true>(path) : scalesKernelFor<false>(path);
    parallelFor(m, springChunk,
                [&](std::size_t begin, std::size_t end) { computeSpringScales(scales, args, begin, end); });
    const GatherKernel gather = gatherKernelFor(path);
    parallelFor(n, massChunkSize, [&](std::size_t begin, std::size_t end) {
        gatherSpringForces(gather, args, begin, end);
        for (std::size_t i = begin; i < end; ++i)
        {
            force[i] = Vec3(pf[i], pf[i + n], pf[i + 2 * n]);
        }
    });
}
} // namespace

void accumulateSpringForces(const SpringSet& springs, Real repulsion, const std::vector<Vec3>& x,
                            const std::vector<Vec3>& v, std::vector<Vec3>& force)
{
    springForcesInto(springs, repulsion, x, v, force, [&](std::size_t i) { return force[i]; });
}

void evaluateForces(const MassSpringSystem& system, const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                    std::vector<Vec3>& force)
{
    const Particles& p = system.particles;
    force.resize(p.size());
    const Vec3 gravity = system.forces.gravity;
    const Real drag = system.forces.airDamping;
    springForcesInto(system.springs, system.forces.repulsion, x, v, force, [&](std::size_t i) {
        return Vec3(p.mass[i] * (gravity - drag * v[i]) + p.externalForce[i]);
    });
    for (const UserSpring& spring : system.userSprings.all())
    {
        force[spring.mass] += evaluateUserSpring(spring, x[spring.mass], v[spring.mass]).force;
    }
}
} // namespace masse
