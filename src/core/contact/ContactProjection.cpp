#include "core/contact/ContactProjection.h"

#include "core/forces/SimdColumns.h"
#include "core/forces/SimdPath.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace masse
{
namespace
{
#if MASSE_SIMD_COLUMNS
using namespace simd;

/// projectEntry on still surfaces for entries [first, first + 8), eight lanes at once, if these are eight
/// consecutive masses (the lattice numbers a layer's masses in a row) with one plane each, free, not stuck, on one
/// obstacle that does not stick and was touched before (so no first contact to list), and, Constrained, neither
/// resting nor arriving in the solve. Returns false, having changed nothing, for any other eight.
///
/// Every lane does projectEntry's operations in its order; its branches become masks, and a lane the scalar code
/// would leave alone is stored back unchanged. Each mass gets the very bits the scalar code gives it.
template <bool Constrained> MASSE_AVX512 bool projectEightStill(const ContactProjection& c, std::size_t first)
{
    const ContactPlanes& planes = c.planes;
    const ContactPlanes::Entry* entries = planes.entries();
    const Index i0 = entries[first].mass;
    const std::size_t k0 = entries[first].firstPlane;
    if (entries[first + 7].mass != i0 + 7 || entries[first + 8].firstPlane != k0 + 8)
    {
        return false;
    }
    Particles& p = c.particles;
    std::uint64_t eightFlags = 0;
    std::memcpy(&eightFlags, &p.pinned[i0], 8);
    if (eightFlags != 0)
    {
        return false;
    }
    if (c.stuck.any)
    {
        std::memcpy(&eightFlags, &c.stuck.stuck[i0], 8);
        if (eightFlags != 0)
        {
            return false;
        }
    }
    if (c.startOverlap.any)
    {
        for (Index i = i0; i < i0 + 8; ++i)
        {
            if (c.startOverlap.depth[i] != 0)
            {
                return false;
            }
        }
    }
    const int* const obstacles = planes.obstacles() + k0;
    const int obstacle = obstacles[0];
    for (int l = 1; l < 8; ++l)
    {
        if (obstacles[l] != obstacle)
        {
            return false;
        }
    }
    const ContactResponse response = c.settings.responseOf(obstacle);
    if (response == ContactResponse::Sticky || c.report.isFirstTouch(obstacle))
    {
        return false;
    }
    if constexpr (Constrained)
    {
        for (Index i = i0; i < i0 + 8; ++i)
        {
            if (c.constraints.resting(i) || c.constraints.arrived(i))
            {
                return false;
            }
        }
    }

    const __m512d zero = _mm512_setzero_pd();
    const Columns n{_mm512_loadu_pd(planes.normalX() + k0), _mm512_loadu_pd(planes.normalY() + k0),
                    _mm512_loadu_pd(planes.normalZ() + k0)};
    Real* const positions = p.position[i0].data();
    const Columns x = loadColumns(positions);
    // The scalar code adds the surface's travel to the offset, ((n . u) elapsed with u = +0: a zero), and takes u from
    // the velocity (v - 0). Both leave every bit as it was here, so they are left out: v - (+0) is v, -0 included; and
    // offset + (±0) differs from the offset only in the sign of a zero offset, which (dot - offset) - radius does not
    // keep (the two differences of a zero dot differ only in a zero's sign, and subtracting the radius, positive,
    // gives the same -radius).
    const __m512d separation =
        _mm512_sub_pd(_mm512_sub_pd(dot(n, x.x, x.y, x.z), _mm512_loadu_pd(planes.offsets() + k0)),
                      _mm512_set1_pd(c.settings.radius));
    // Not "less than": a NaN separation touches, as it does in the scalar code.
    const __mmask8 touches =
        _mm512_cmp_pd_mask(separation, _mm512_set1_pd(Real(1e-6) * c.settings.radius), _CMP_NGE_UQ);
    if (touches == 0)
    {
        return true;
    }
    const __mmask8 inside = _mm512_cmp_pd_mask(separation, zero, _CMP_LT_OQ);
    Columns y{_mm512_mask_sub_pd(x.x, inside, x.x, _mm512_mul_pd(separation, n.x)),
              _mm512_mask_sub_pd(x.y, inside, x.y, _mm512_mul_pd(separation, n.y)),
              _mm512_mask_sub_pd(x.z, inside, x.z, _mm512_mul_pd(separation, n.z))};

    Real* const velocities = p.velocity[i0].data();
    const Columns v = loadColumns(velocities);
    const __m512d normalSpeed = dot(n, v.x, v.y, v.z);
    const __mmask8 stops = touches & _mm512_cmp_pd_mask(normalSpeed, zero, _CMP_NGE_UQ);
    if (stops != 0)
    {
        __m512d tx = _mm512_sub_pd(v.x, _mm512_mul_pd(normalSpeed, n.x));
        __m512d ty = _mm512_sub_pd(v.y, _mm512_mul_pd(normalSpeed, n.y));
        __m512d tz = _mm512_sub_pd(v.z, _mm512_mul_pd(normalSpeed, n.z));
        if (response == ContactResponse::Friction)
        {
            const __m512d budget = _mm512_mul_pd(_mm512_set1_pd(c.settings.frictionOf(obstacle)), negated(normalSpeed));
            const __m512d squared =
                _mm512_add_pd(_mm512_add_pd(_mm512_mul_pd(tx, tx), _mm512_mul_pd(ty, ty)), _mm512_mul_pd(tz, tz));
            // (Masked with every lane set: the unmasked form reads a register GCC 12 warns is undefined.)
            const __m512d speed = _mm512_mask_sqrt_pd(squared, 0xFF, squared);
            const __mmask8 slides = _mm512_cmp_pd_mask(speed, budget, _CMP_NLE_UQ);
            const __m512d keep = _mm512_div_pd(_mm512_sub_pd(speed, budget), speed);
            // Held lanes get +0, as the scalar code sets.
            tx = _mm512_maskz_mul_pd(slides, tx, keep);
            ty = _mm512_maskz_mul_pd(slides, ty, keep);
            tz = _mm512_maskz_mul_pd(slides, tz, keep);
        }
        const Columns w{_mm512_mask_add_pd(v.x, stops, zero, tx), _mm512_mask_add_pd(v.y, stops, zero, ty),
                        _mm512_mask_add_pd(v.z, stops, zero, tz)};
        const __m512d dx = _mm512_sub_pd(w.x, v.x);
        const __m512d dy = _mm512_sub_pd(w.y, v.y);
        const __m512d dz = _mm512_sub_pd(w.z, v.z);
        const __m512d along = dot(n, dx, dy, dz);
        const __m512d moveStep = _mm512_set1_pd(c.moveStep);
        y.x =
            _mm512_mask_add_pd(y.x, stops, y.x, _mm512_mul_pd(moveStep, _mm512_sub_pd(dx, _mm512_mul_pd(along, n.x))));
        y.y =
            _mm512_mask_add_pd(y.y, stops, y.y, _mm512_mul_pd(moveStep, _mm512_sub_pd(dy, _mm512_mul_pd(along, n.y))));
        y.z =
            _mm512_mask_add_pd(y.z, stops, y.z, _mm512_mul_pd(moveStep, _mm512_sub_pd(dz, _mm512_mul_pd(along, n.z))));
        storeColumns(velocities, w);

        // The impulses are added as they lie in memory, x y z of one mass after another: only the change needs
        // rearranging. A lane that stopped nothing adds +0, which leaves its impulse as it was: an impulse starts the
        // frame at +0 and only has changes added, so it is never -0.
        Real* const impulses = c.report.impulseData() + 3 * std::size_t(i0);
        const __m512d m = _mm512_loadu_pd(p.mass.data() + i0);
        const Rows change = rowsOf(
            {_mm512_maskz_mul_pd(stops, m, dx), _mm512_maskz_mul_pd(stops, m, dy), _mm512_maskz_mul_pd(stops, m, dz)});
        _mm512_storeu_pd(impulses, _mm512_add_pd(_mm512_loadu_pd(impulses), change.first));
        _mm512_storeu_pd(impulses + 8, _mm512_add_pd(_mm512_loadu_pd(impulses + 8), change.second));
        _mm512_storeu_pd(impulses + 16, _mm512_add_pd(_mm512_loadu_pd(impulses + 16), change.third));
    }
    storeColumns(positions, y);

    // ContactReport::touchInChunk: a mass's first touch this frame names the obstacle and face.
    int* const touchedObstacle = c.report.touchingObstacleData() + i0;
    const __mmask16 lower = 0xFF;
    const __mmask16 untouched = _mm512_mask_cmplt_epi32_mask(
        __mmask16(touches) & lower, _mm512_maskz_loadu_epi32(lower, touchedObstacle), _mm512_setzero_si512());
    if (untouched != 0) // (after the frame's first substep, rarely)
    {
        _mm512_mask_storeu_epi32(touchedObstacle, untouched, _mm512_set1_epi32(obstacle));
        _mm512_mask_storeu_epi32(c.report.touchingFaceData() + i0, untouched,
                                 _mm512_maskz_loadu_epi32(lower, planes.faces() + k0));
    }
    return true;
}
#endif
} // namespace

void ContactProjection::run(std::size_t begin, std::size_t end, std::vector<int>& firstTouches, bool& madeStuck) const
{
    const bool still = planes.stillRun(begin / ContactPlanes::runLength);
    const bool constrained = constraints.any();
    if (still && !constrained)
    {
        projectRange<true, false>(begin, end, firstTouches, madeStuck);
    }
    else if (still)
    {
        projectRange<true, true>(begin, end, firstTouches, madeStuck);
    }
    else if (!constrained)
    {
        projectRange<false, false>(begin, end, firstTouches, madeStuck);
    }
    else
    {
        projectRange<false, true>(begin, end, firstTouches, madeStuck);
    }
}

template <bool Still, bool Constrained>
void ContactProjection::projectRange(std::size_t begin, std::size_t end, std::vector<int>& firstTouches,
                                     bool& madeStuck) const
{
    std::size_t j = begin;
#if MASSE_SIMD_COLUMNS
    // Most masses near a still surface come in eights that projectEightStill takes at once, branch-free, in about
    // 150 instructions for the eight, where the scalar code below takes about as many for each mass.
    if constexpr (Still)
    {
        if (activeSimdPath() == SimdPath::Avx512)
        {
            for (; j + 8 <= end; j += 8)
            {
                if (!projectEightStill<Constrained>(*this, j))
                {
                    for (std::size_t l = j; l < j + 8; ++l)
                    {
                        projectEntry<Still, Constrained>(l, firstTouches, madeStuck);
                    }
                }
            }
        }
    }
#endif
    for (; j < end; ++j)
    {
        projectEntry<Still, Constrained>(j, firstTouches, madeStuck);
    }
}

// The arithmetic is spelt out per coordinate, in the order Eigen's 3-vector operations take (a dot product sums
// (x + y) + z): the same bits as the vector form, in about a third fewer instructions than Eigen's two-and-one split
// of a 3-vector into SSE2 registers, which is what this kernel's time would go to.
template <bool Still, bool Constrained>
void ContactProjection::projectEntry(std::size_t j, std::vector<int>& firstTouches, bool& madeStuck) const
{
    Particles& p = particles;
    const Real radius = settings.radius;
    const Real touchTolerance = Real(1e-6) * radius;
    const Index i = planes.mass(j);
    for (std::size_t k = planes.firstPlane(j); k < planes.endPlane(j); ++k)
    {
        if (p.pinned[i] || stuck.stuck[i])
        {
            continue; // (a plane earlier in this loop may have just made it stuck)
        }
        const ContactPlanes::Surface plane = planes.surface(k);
        const Real nx = plane.normal.x();
        const Real ny = plane.normal.y();
        const Real nz = plane.normal.z();
        // A still surface's velocity is +0 in every bit, so the constant gives the very same arithmetic.
        const Vec3 surfaceVelocity = Still ? Vec3(Vec3::Zero()) : planes.velocity(k);
        const Real ux = surfaceVelocity.x();
        const Real uy = surfaceVelocity.y();
        const Real uz = surfaceVelocity.z();
        Real* const x = p.position[i].data();
        const Real offset = plane.offset + ((nx * ux + ny * uy) + nz * uz) * elapsed;
        Real separation = ((nx * x[0] + ny * x[1]) + nz * x[2]) - offset - radius;
        if (startOverlap.any)
        {
            separation += startOverlap.depth[i]; // (+0 for a mass without one: the comparisons below see the same)
        }
        bool arrived = false;
        if constexpr (Constrained)
        {
            if (constraints.resting(i) && constraints.restingPlane(i) == k)
            {
                // The solve kept this resting mass moving with its surface; only a position error is left to mend
                // (say, a surface that started moving within the last frame).
                if (separation < 0)
                {
                    x[0] -= separation * nx;
                    x[1] -= separation * ny;
                    x[2] -= separation * nz;
                }
                continue;
            }
            // A mass that arrived at this surface in the solve: the solve stopped its approach with an impulse,
            // which gives its friction as the approach the projection stops gives any other's.
            arrived = constraints.arrived(i) && constraints.restingPlane(i) == k;
        }
        if (separation >= touchTolerance && !arrived)
        {
            continue;
        }
        if (separation < 0)
        {
            x[0] -= separation * nx;
            x[1] -= separation * ny;
            x[2] -= separation * nz;
        }
        report.touchInChunk(i, plane.obstacle, plane.face, firstTouches);

        Real* const v = p.velocity[i].data();
        const Real rx = v[0] - ux;
        const Real ry = v[1] - uy;
        const Real rz = v[2] - uz;
        const Real normalSpeed = (rx * nx + ry * ny) + rz * nz;
        Real stopped = -normalSpeed; // the normal speed the contact takes away
        if (arrived)
        {
            stopped =
                std::max(Real(0), -normalSpeed) + std::max(Real(0), constraints.arrivalImpulse(i)) * p.inverseMass[i];
        }
        else if (normalSpeed >= 0)
        {
            continue; // already leaving the surface
        }
        Real tx = rx - normalSpeed * nx;
        Real ty = ry - normalSpeed * ny;
        Real tz = rz - normalSpeed * nz;
        const ContactResponse response = settings.responseOf(plane.obstacle);
        switch (response)
        {
        case ContactResponse::Sticky:
            tx = 0;
            ty = 0;
            tz = 0;
            break;
        case ContactResponse::Friction:
        {
            const Real budget = settings.frictionOf(plane.obstacle) * stopped;
            const Real speed = std::sqrt((tx * tx + ty * ty) + tz * tz);
            if (speed <= budget)
            {
                tx = 0;
                ty = 0;
                tz = 0;
            }
            else
            {
                const Real keep = (speed - budget) / speed;
                tx *= keep;
                ty *= keep;
                tz *= keep;
            }
            break;
        }
        case ContactResponse::Frictionless:
            break;
        }
        const Real before[3] = {v[0], v[1], v[2]};
        v[0] = ux + tx;
        v[1] = uy + ty;
        v[2] = uz + tz;
        const Real dx = v[0] - before[0];
        const Real dy = v[1] - before[1];
        const Real dz = v[2] - before[2];
        const Real m = p.mass[i];
        report.addImpulse(i, Vec3(m * dx, m * dy, m * dz));
        // The integrator already moved the mass with its velocity from before the contact. Move it by the
        // tangential change too, as if the impulse had come first; otherwise a mass held by static friction
        // would creep by h^2 g sin(a) every substep. (The normal part is handled by the projection.) BDF2 moves a
        // mass by 2h/3 of its new velocity: moved by h, a mass against an obstacle's side would lose more of its slide
        // than its velocity does, and the two would never agree again (the drop scene's sheet would slide on along the
        // valley).
        const Real along = (dx * nx + dy * ny) + dz * nz;
        x[0] += moveStep * (dx - along * nx);
        x[1] += moveStep * (dy - along * ny);
        x[2] += moveStep * (dz - along * nz);
        if (response == ContactResponse::Sticky)
        {
            stuck.stick(i, p.position[i], planes[k]);
            madeStuck = true;
        }
    }
}
} // namespace masse
