#include "core/forces/SpringEnergyKernels.h"

#include "core/forces/SpringForce.h"

#include <algorithm>
#include <cmath>

namespace masse
{
namespace
{
/// Springs per block: the computing loop's arrays stay in the first-level cache.
constexpr std::size_t energyBlock = 128;

[[gnu::always_inline]] inline Real springEnergyBody(const MassSpringSystem& system, std::size_t begin, std::size_t end)
{
    const SpringSet& s = system.springs;
    const SpringEnds* __restrict ends = s.ends().data();
    const Vec3* __restrict x = system.particles.position.data();
    const Real repulsion = system.forces.repulsion;
    Real lengthSquared[energyBlock];
    Real energy[energyBlock];
    Real sum = 0;
    for (std::size_t first = begin; first < end; first += energyBlock)
    {
        const std::size_t n = std::min(energyBlock, end - first);
        for (std::size_t j = 0; j < n; ++j)
        {
            lengthSquared[j] = (x[ends[first + j].a] - x[ends[first + j].b]).squaredNorm();
        }
        const Real* __restrict rest = s.restLength().data() + first;
        const Real* __restrict stiffness = s.stiffness().data() + first;
        for (std::size_t j = 0; j < n; ++j)
        {
            energy[j] = springPotential(std::sqrt(lengthSquared[j]), stiffness[j], rest[j], repulsion);
        }
        for (std::size_t j = 0; j < n; ++j) // in spring order
        {
            sum += energy[j];
        }
    }
    return sum;
}

[[gnu::always_inline]] inline SpringEnergyAndGap springEnergyAndGapBody(const MassSpringSystem& system,
                                                                        const std::vector<Vec3>& startPositions,
                                                                        std::size_t begin, std::size_t end)
{
    const SpringSet& s = system.springs;
    const SpringEnds* __restrict ends = s.ends().data();
    const Vec3* __restrict x = system.particles.position.data();
    const Vec3* __restrict start = startPositions.data();
    const Real repulsion = system.forces.repulsion;
    // Per spring of the block: |d1|^2 now, d0 at the start, and the move of a relative to b within the substep.
    Real lengthSquared[energyBlock];
    Real d0[3][energyBlock];
    Real move[3][energyBlock];
    Real energy[energyBlock];
    Real gap[energyBlock];
    SpringEnergyAndGap sum;
    for (std::size_t first = begin; first < end; first += energyBlock)
    {
        const std::size_t n = std::min(energyBlock, end - first);
        for (std::size_t j = 0; j < n; ++j)
        {
            const Index a = ends[first + j].a;
            const Index b = ends[first + j].b;
            lengthSquared[j] = (x[a] - x[b]).squaredNorm();
            const Vec3 startD = start[a] - start[b];
            const Vec3 moved = (x[a] - start[a]) - (x[b] - start[b]);
            for (int c = 0; c < 3; ++c)
            {
                d0[c][j] = startD[c];
                move[c][j] = moved[c];
            }
        }
        const Real* __restrict rest = s.restLength().data() + first;
        const Real* __restrict stiffness = s.stiffness().data() + first;
        for (std::size_t j = 0; j < n; ++j)
        {
            const Real L = rest[j];
            const Real k = stiffness[j];
            const Real l1 = std::sqrt(lengthSquared[j]);
            energy[j] = springPotential(l1, k, L, repulsion);
            // The quadratic model the linearised solve minimised: the spring's energy at the start, its force and
            // its stiffness there (the compressed spring's negative transverse stiffness left out, as the solver
            // leaves it out), along the move.
            const Real l0 = std::sqrt((d0[0][j] * d0[0][j] + d0[1][j] * d0[1][j]) + d0[2][j] * d0[2][j]);
            const Real nx = d0[0][j] / l0;
            const Real ny = d0[1][j] / l0;
            const Real nz = d0[2][j] / l0;
            const Real along = (nx * move[0][j] + ny * move[1][j]) + nz * move[2][j];
            const Real ax = move[0][j] - along * nx;
            const Real ay = move[1][j] - along * ny;
            const Real az = move[2][j] - along * nz;
            const Real across = (ax * ax + ay * ay) + az * az;
            const Real model = Real(0.5) * k *
                               ((l0 - L) * (l0 - L) + Real(2) * (l0 - L) * along + along * along +
                                std::max(Real(0), Real(1) - L / l0) * across);
            const Real excess = std::max(Real(0), Real(0.5) * k * (l1 - L) * (l1 - L) - model);
            // A spring too short at the start to have a direction had no linear model: no gap.
            gap[j] = l0 > degenerateLengthFraction * L ? excess : Real(0);
        }
        for (std::size_t j = 0; j < n; ++j) // in spring order
        {
            sum.energy += energy[j];
            sum.gap += gap[j];
        }
    }
    return sum;
}

// One copy of each kernel per SIMD path; only the instruction set differs (SimdPath.h).
#define MASSE_SPRING_ENERGY_KERNELS(suffix, targetAttribute)                                                           \
    targetAttribute Real springEnergy##suffix(const MassSpringSystem& system, std::size_t begin, std::size_t end)      \
    {                                                                                                                  \
        return springEnergyBody(system, begin, end);                                                                   \
    }                                                                                                                  \
    targetAttribute SpringEnergyAndGap springEnergyAndGap##suffix(                                                     \
        const MassSpringSystem& system, const std::vector<Vec3>& start, std::size_t begin, std::size_t end)            \
    {                                                                                                                  \
        return springEnergyAndGapBody(system, start, begin, end);                                                      \
    }

MASSE_SPRING_ENERGY_KERNELS(Default, )
#if defined(__x86_64__) && defined(__GNUC__)
MASSE_SPRING_ENERGY_KERNELS(Avx2, __attribute__((target("avx2"))))
MASSE_SPRING_ENERGY_KERNELS(Avx512, __attribute__((target("avx512f"))))
#endif
#undef MASSE_SPRING_ENERGY_KERNELS
} // namespace

Real springEnergyOfRange(SimdPath path, const MassSpringSystem& system, std::size_t begin, std::size_t end)
{
    switch (path)
    {
#if defined(__x86_64__) && defined(__GNUC__)
    case SimdPath::Avx512:
        return springEnergyAvx512(system, begin, end);
    case SimdPath::Avx2:
        return springEnergyAvx2(system, begin, end);
#endif
    default:
        return springEnergyDefault(system, begin, end);
    }
}

SpringEnergyAndGap springEnergyAndGapOfRange(SimdPath path, const MassSpringSystem& system,
                                             const std::vector<Vec3>& start, std::size_t begin, std::size_t end)
{
    switch (path)
    {
#if defined(__x86_64__) && defined(__GNUC__)
    case SimdPath::Avx512:
        return springEnergyAndGapAvx512(system, start, begin, end);
    case SimdPath::Avx2:
        return springEnergyAndGapAvx2(system, start, begin, end);
#endif
    default:
        return springEnergyAndGapDefault(system, start, begin, end);
    }
}
} // namespace masse
