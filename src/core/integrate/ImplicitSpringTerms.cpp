#include "core/integrate/ImplicitSpringTerms.h"

#include "core/forces/SpringForce.h"

#include <algorithm>
#include <cmath>

namespace masse
{
namespace
{
/// Springs per block: the computing loop's arrays stay in the first-level cache.
constexpr std::size_t termBlock = 64;

[[gnu::always_inline]] inline void springTermsBody(const MassSpringSystem& system, const SpringTermInputs& inputs,
                                                   std::size_t begin, std::size_t end, SpringTerm* __restrict terms,
                                                   std::uint8_t* __restrict engaged)
{
    const SpringSet& springs = system.springs;
    const SpringEnds* __restrict ends = springs.ends().data();
    const Vec3* __restrict x = system.particles.position.data();
    const Vec3* __restrict v = system.particles.velocity.data();
    const bool hasOffset = inputs.offset && !inputs.offset->empty();
    const Vec3* __restrict offset = hasOffset ? inputs.offset->data() : nullptr;
    const Real a = inputs.a;
    const Real a2 = a * a;
    const Real repulsion = system.forces.repulsion;
    const bool withRepulsion = repulsion > 0;
    // Per spring of the block: d = x_a - x_b and its squared length, the move (a (v_a - v_b) + offset_a - offset_b),
    // then the term's nine figures.
    Real d[3][termBlock];
    Real lengthSquared[termBlock];
    Real move[3][termBlock];
    Real upper[6][termBlock];
    Real kv[3][termBlock];
    Real lengthOf[termBlock];
    for (std::size_t first = begin; first < end; first += termBlock)
    {
        const std::size_t n = std::min(termBlock, end - first);
        for (std::size_t j = 0; j < n; ++j)
        {
            const Index ea = ends[first + j].a;
            const Index eb = ends[first + j].b;
            const Vec3 dj = x[ea] - x[eb];
            lengthSquared[j] = dj.squaredNorm();
            Vec3 mj = a * (v[ea] - v[eb]);
            if (hasOffset)
            {
                mj += offset[ea] - offset[eb];
            }
            for (int c = 0; c < 3; ++c)
            {
                d[c][j] = dj[c];
                move[c][j] = mj[c];
            }
        }
        const Real* __restrict rest = springs.restLength().data() + first;
        const Real* __restrict stiffness = springs.stiffness().data() + first;
        const Real* __restrict damping = springs.damping().data() + first;
        for (std::size_t j = 0; j < n; ++j)
        {
            const Real length = std::sqrt(lengthSquared[j]);
            lengthOf[j] = length;
            const Real nx = d[0][j] / length;
            const Real ny = d[1][j] / length;
            const Real nz = d[2][j] / length;
            const Real k = stiffness[j];
            Real axial = k;
            if (withRepulsion && length < rest[j])
            {
                axial += Real(2) * repulsion / (length * length * length);
            }
            const Real transverse = k * std::max(Real(0), Real(1) - rest[j] / length);
            const Real dampingTerm = a * damping[j];
            // The stiffness block -K_aa = axial n n^T + transverse (I - n n^T), entry by entry as Eigen forms it
            // (the identity's zeros included: 0 - n_r n_c, not -n_r n_c, for the bits of a signed zero).
            const Real xx = nx * nx;
            const Real xy = nx * ny;
            const Real xz = nx * nz;
            const Real yy = ny * ny;
            const Real yz = ny * nz;
            const Real zz = nz * nz;
            const Real sxx = axial * xx + transverse * (Real(1) - xx);
            const Real sxy = axial * xy + transverse * (Real(0) - xy);
            const Real sxz = axial * xz + transverse * (Real(0) - xz);
            const Real syy = axial * yy + transverse * (Real(1) - yy);
            const Real syz = axial * yz + transverse * (Real(0) - yz);
            const Real szz = axial * zz + transverse * (Real(1) - zz);
            upper[0][j] = dampingTerm * xx + a2 * sxx;
            upper[1][j] = dampingTerm * xy + a2 * sxy;
            upper[2][j] = dampingTerm * xz + a2 * sxz;
            upper[3][j] = dampingTerm * yy + a2 * syy;
            upper[4][j] = dampingTerm * yz + a2 * syz;
            upper[5][j] = dampingTerm * zz + a2 * szz;
            const Real mx = move[0][j];
            const Real my = move[1][j];
            const Real mz = move[2][j];
            // a (S m) in the order Eigen evaluated it before, so that the step keeps its bits: the scalar moves into
            // the product's left factor, (a S) m; the first two rows as one SSE2 packet, (p0 + p1) + p2; the third
            // alone, through Eigen's halving sum, p0 + (p1 + p2).
            kv[0][j] = ((a * sxx) * mx + (a * sxy) * my) + (a * sxz) * mz;
            kv[1][j] = ((a * sxy) * mx + (a * syy) * my) + (a * syz) * mz;
            kv[2][j] = (a * sxz) * mx + ((a * syz) * my + (a * szz) * mz);
        }
        for (std::size_t j = 0; j < n; ++j)
        {
            SpringTerm& term = terms[first + j];
            for (int e = 0; e < 6; ++e)
            {
                term.upper[std::size_t(e)] = upper[e][j];
            }
            term.kv = Vec3(kv[0][j], kv[1][j], kv[2][j]);
            engaged[first + j] = lengthOf[j] > degenerateLengthFraction * rest[j];
        }
    }
}

// One copy per SIMD path; only the instruction set differs (SimdPath.h).
#define MASSE_SPRING_TERM_KERNELS(suffix, targetAttribute)                                                             \
    targetAttribute void springTerms##suffix(const MassSpringSystem& system, const SpringTermInputs& inputs,           \
                                             std::size_t begin, std::size_t end, SpringTerm* terms,                    \
                                             std::uint8_t* engaged)                                                    \
    {                                                                                                                  \
        springTermsBody(system, inputs, begin, end, terms, engaged);                                                   \
    }

MASSE_SPRING_TERM_KERNELS(Default, )
#if defined(__x86_64__) && defined(__GNUC__)
MASSE_SPRING_TERM_KERNELS(Avx2, __attribute__((target("avx2"))))
MASSE_SPRING_TERM_KERNELS(Avx512, __attribute__((target("avx512f"))))
#endif
#undef MASSE_SPRING_TERM_KERNELS
} // namespace

void computeSpringTerms(SimdPath path, const MassSpringSystem& system, const SpringTermInputs& inputs,
                        std::size_t begin, std::size_t end, SpringTerm* terms, std::uint8_t* engaged)
{
    switch (path)
    {
#if defined(__x86_64__) && defined(__GNUC__)
    case SimdPath::Avx512:
        return springTermsAvx512(system, inputs, begin, end, terms, engaged);
    case SimdPath::Avx2:
        return springTermsAvx2(system, inputs, begin, end, terms, engaged);
#endif
    default:
        return springTermsDefault(system, inputs, begin, end, terms, engaged);
    }
}
} // namespace masse
