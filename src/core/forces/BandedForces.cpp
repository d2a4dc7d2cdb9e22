/// The banded spring-force kernel (see BandedForces.h and SpringRowPlan.h).
///
/// A band first copies its masses' positions and velocities into a structure of arrays (one array per component), so
/// that every loop after it loads and stores contiguously and vectorises across neighbouring springs or masses. Then,
/// row by row, it computes the forces F = scale * d of the row's springs once each, with the arithmetic of the plain
/// kernel (Forces.cpp, springScalesBody), into a small per-row scratch, and each mass of the row sums its own force and
/// its springs' in the plan's order: +F where it is end a, -F where it is end b, the bits of the plain gather (which
/// adds scale * (x_b - x_a) = -F exactly). A band's rows touch only its own masses, except its last row, whose springs
/// reach into the next band: those rows are computed before any band starts, from the masses' own arrays. So a band
/// may move its masses (the symplectic kick and drift, fused into the same pass) without another band ever reading a
/// moved mass, and nothing depends on which thread runs which band.

#include "core/forces/BandedForces.h"

#include "core/forces/SimdPath.h"
#include "core/forces/SpringForce.h"
#include "core/parallel/TaskPool.h"

#include <algorithm>
#include <cmath>
#include <vector>

// "These iterations are independent": GCC's ivdep, clang's assume_safety (clang ignores GCC's pragma with a warning).
#if defined(__clang__)
#define MASSE_IVDEP _Pragma("clang loop vectorize(assume_safety)")
#else
#define MASSE_IVDEP _Pragma("GCC ivdep")
#endif
namespace masse
{
namespace
{
constexpr bool isSymplectic(BandedPass pass)
{
    return pass == BandedPass::SymplecticSubstep || pass == BandedPass::SymplecticSubstepWithoutExternalForces;
}

/// A pass as the kernels are compiled for it: what it computes, and whether it stores the forces (a symplectic
/// substep whose forces nobody reads skips the store, a sixth of the memory the pass streams).
struct PassConfig
{
    BandedPass pass;
    bool storeForce;
};

/// The spring forces of one spring row: x, y and z components of slot s at x[s], x[slots + s], x[2 * slots + s].
struct RowForces
{
    Real* x = nullptr;
    std::size_t slots = 0;
};

/// A band's copy of its masses' state: component c of local mass i at position[c * stride + i].
struct BandState
{
    Real* position = nullptr;
    Real* velocity = nullptr;
    std::size_t stride = 0;
};

/// The stiffness and damping of a run of springs: per spring, or one pair for the whole run.
struct RunCoefficients
{
    const Real* stiffness = nullptr;
    const Real* damping = nullptr;
    Real uniformStiffness = 0;
    Real uniformDamping = 0;
};

/// The forces of `n` springs whose ends' components are read with `stride` (3: the masses' own arrays of Vec3; 1: a
/// band's copy), into three component arrays. The arithmetic is springScalesBody's, term for term: Eigen's squaredNorm
/// and dot of 3-vectors sum (x + y) + z. With `uniform`, every spring takes the run's one stiffness and damping, which
/// saves streaming two arrays from memory (the same values, so the same bits).
template <bool withRepulsion, std::size_t stride, bool uniform>
[[gnu::always_inline]] inline void
springLoop(std::size_t n, const Real* __restrict xa, const Real* __restrict xb, std::size_t xComponent,
           const Real* __restrict va, const Real* __restrict vb, std::size_t vComponent, const Real* __restrict rest,
           const RunCoefficients& coefficients, Real repulsion, Real* __restrict fx, std::size_t fComponent)
{
    const Real* __restrict stiffness = coefficients.stiffness;
    const Real* __restrict damping = coefficients.damping;
    const Real uniformStiffness = coefficients.uniformStiffness;
    const Real uniformDamping = coefficients.uniformDamping;
    // Nothing here aliases (spring forces go to the row scratch), but GCC cannot tell once this is inlined, and the
    // run-time alias checks it would need exceed its limit: without ivdep the loops stay scalar.
    MASSE_IVDEP
    for (std::size_t j = 0; j < n; ++j)
    {
        const Real dx = xa[stride * j] - xb[stride * j];
        const Real dy = xa[xComponent + stride * j] - xb[xComponent + stride * j];
        const Real dz = xa[2 * xComponent + stride * j] - xb[2 * xComponent + stride * j];
        const Real ux = va[stride * j] - vb[stride * j];
        const Real uy = va[vComponent + stride * j] - vb[vComponent + stride * j];
        const Real uz = va[2 * vComponent + stride * j] - vb[2 * vComponent + stride * j];
        const Real lengthSquared = (dx * dx + dy * dy) + dz * dz;
        const Real speedTimesLength = (ux * dx + uy * dy) + uz * dz;
        const Real length = std::sqrt(lengthSquared);
        const Real inverse = Real(1) / length;
        Real magnitude = hookeMagnitude(length, speedTimesLength * inverse, uniform ? uniformStiffness : stiffness[j],
                                        uniform ? uniformDamping : damping[j], rest[j]);
        if constexpr (withRepulsion)
        {
            magnitude += repulsionMagnitude(length, rest[j], repulsion);
        }
        const Real scale = length > degenerateLengthFraction * rest[j] ? magnitude * inverse : Real(0);
        fx[j] = scale * dx;
        fx[fComponent + j] = scale * dy;
        fx[2 * fComponent + j] = scale * dz;
    }
}

/// A run's coefficients: its class's pair when the set has one per class, else its springs' own.
RunCoefficients runCoefficients(const SpringSet& springs, const SpringRowPlan::SpringRun& run)
{
    RunCoefficients c;
    if (const UniformClassCoefficients* uniform = springs.uniformCoefficients())
    {
        c.uniformStiffness = uniform->stiffness[run.springClass];
        c.uniformDamping = uniform->damping[run.springClass];
    }
    else
    {
        c.stiffness = springs.stiffness().data() + run.firstSpring;
        c.damping = springs.damping().data() + run.firstSpring;
    }
    return c;
}

/// The forces of one run into its row's slots: from the masses' own arrays (stride 3) or a band's copy (stride 1).
template <bool withRepulsion, std::size_t stride>
[[gnu::always_inline]] inline void springRun(const SpringSet& springs, const SpringRowPlan::SpringRun& run,
                                             const Real* xa, const Real* xb, std::size_t xComponent, const Real* va,
                                             const Real* vb, std::size_t vComponent, Real repulsion,
                                             const RowForces& out)
{
    const RunCoefficients coefficients = runCoefficients(springs, run);
    const Real* rest = springs.restLength().data() + run.firstSpring;
    if (coefficients.stiffness == nullptr)
    {
        springLoop<withRepulsion, stride, true>(run.count, xa, xb, xComponent, va, vb, vComponent, rest, coefficients,
                                                repulsion, out.x + run.firstSlot, out.slots);
    }
    else
    {
        springLoop<withRepulsion, stride, false>(run.count, xa, xb, xComponent, va, vb, vComponent, rest, coefficients,
                                                 repulsion, out.x + run.firstSlot, out.slots);
    }
}

/// A spring row from the masses' own arrays (the rows between bands).
template <bool withRepulsion>
[[gnu::always_inline]] inline void springRowFromArrays(const SpringRowPlan& plan, const BandedForceArgs& args,
                                                       std::size_t row, const RowForces& out)
{
    for (Index k = plan.springRunStart[row]; k < plan.springRunStart[row + 1]; ++k)
    {
        const SpringRowPlan::SpringRun& run = plan.springRuns[k];
        springRun<withRepulsion, 3>(*args.springs, run, args.x[run.a].data(), args.x[run.b].data(), 1,
                                    args.v[run.a].data(), args.v[run.b].data(), 1, args.repulsion, out);
    }
}

/// A spring row of a band, from the band's copy.
template <bool withRepulsion>
[[gnu::always_inline]] inline void springRowFromBand(const SpringRowPlan& plan, const BandedForceArgs& args,
                                                     std::size_t row, const BandState& state, const RowForces& out)
{
    for (Index k = plan.springRunStart[row]; k < plan.springRunStart[row + 1]; ++k)
    {
        const SpringRowPlan::SpringRun& run = plan.springRuns[k];
        springRun<withRepulsion, 1>(*args.springs, run, state.position + run.aLocal, state.position + run.bLocal,
                                    state.stride, state.velocity + run.aLocal, state.velocity + run.bLocal,
                                    state.stride, args.repulsion, out);
    }
}

/// Copies `n` Vec3 into three component arrays `stride` apart.
[[gnu::always_inline]] inline void splitComponents(std::size_t n, const Real* __restrict from, Real* __restrict to,
                                                   std::size_t stride)
{
    MASSE_IVDEP
    for (std::size_t j = 0; j < n; ++j)
    {
        to[j] = from[3 * j];
        to[stride + j] = from[3 * j + 1];
        to[2 * stride + j] = from[3 * j + 2];
    }
}

/// The most entries a mass run's pattern may have for the fused loop (a TRiMM mass has at most 9, SaMM 8, SLaMM 10, a
/// middle layer of a multi-layer SLaMM sheet 14); a longer pattern is summed entry by entry (entryByEntry).
constexpr int maxFusedEntries = 16;

/// Where one entry of a mass run reads its springs' forces.
struct EntrySource
{
    const Real* x; ///< component x of the run's first mass's spring; y and z at + stride, + 2 stride
    std::size_t stride;
    Real sign; ///< +1 at end a, -1 at end b: adding sign * F has the bits of adding F or subtracting it
};

EntrySource entrySource(const SpringRowPlan::Entry& e, const RowForces& previous, const RowForces& current)
{
    const RowForces& row = e.sameRow ? current : previous;
    return {row.x + e.slot, row.slots, e.negated ? Real(-1) : Real(1)};
}

template <PassConfig config>
[[gnu::always_inline]] inline void ownForce(const BandedForceArgs& args, const BandState& state, std::size_t mass,
                                            std::size_t local, Real& fx, Real& fy, Real& fz)
{
    if constexpr (config.pass == BandedPass::AddSpringForces)
    {
        fx = args.force[mass].x();
        fy = args.force[mass].y();
        fz = args.force[mass].z();
    }
    else
    {
        // m (g - drag v) + external, as Eigen evaluates it component by component in the plain gather. Without
        // external forces the sum still adds +0: the same bits as adding an external force of +0 (a -0 would stay -0).
        const Real m = args.mass[mass];
        constexpr bool external = config.pass != BandedPass::SymplecticSubstepWithoutExternalForces;
        fx = m * (args.gravity.x() - args.drag * state.velocity[local]) +
             (external ? args.externalForce[mass].x() : Real(0));
        fy = m * (args.gravity.y() - args.drag * state.velocity[state.stride + local]) +
             (external ? args.externalForce[mass].y() : Real(0));
        fz = m * (args.gravity.z() - args.drag * state.velocity[2 * state.stride + local]) +
             (external ? args.externalForce[mass].z() : Real(0));
    }
}

/// Stores mass `mass`'s force (unless the pass keeps none) and, for the symplectic substep, its kick and drift from the
/// band's copy.
template <PassConfig config>
[[gnu::always_inline]] inline void finishMass(const BandedForceArgs& args, const BandState& state, std::size_t mass,
                                              std::size_t local, Real fx, Real fy, Real fz)
{
    if constexpr (config.storeForce)
    {
        Real* force = args.force[mass].data();
        force[0] = fx;
        force[1] = fy;
        force[2] = fz;
    }
    if constexpr (isSymplectic(config.pass))
    {
        const Real kick = args.h * args.inverseMass[mass];
        const std::size_t s = state.stride;
        const Real vx = state.velocity[local] + kick * fx;
        const Real vy = state.velocity[s + local] + kick * fy;
        const Real vz = state.velocity[2 * s + local] + kick * fz;
        Real* v = args.velocity[mass].data();
        v[0] = vx;
        v[1] = vy;
        v[2] = vz;
        Real* x = args.position[mass].data();
        x[0] = state.position[local] + args.h * vx;
        x[1] = state.position[s + local] + args.h * vy;
        x[2] = state.position[2 * s + local] + args.h * vz;
    }
}

/// Each mass of a run whose pattern has exactly `entryCount` entries sums its force in one pass, the force held in
/// registers while the entries are added in the pattern's order. The count is a template argument so that the loop
/// over entries unrolls and the loop over masses vectorises.
template <PassConfig config, int entryCount>
[[gnu::always_inline]] inline void fusedMassRun(const SpringRowPlan::MassRun& run, const SpringRowPlan::Entry* entries,
                                                const RowForces& previous, const RowForces& current,
                                                const BandedForceArgs& args, const BandState& state)
{
    EntrySource source[entryCount];
    for (int k = 0; k < entryCount; ++k)
    {
        source[k] = entrySource(entries[run.firstEntry + Index(k)], previous, current);
    }
    const std::size_t first = run.firstMass;
    const std::size_t local = run.local;
    MASSE_IVDEP
    for (std::size_t j = 0; j < run.count; ++j)
    {
        Real fx;
        Real fy;
        Real fz;
        ownForce<config>(args, state, first + j, local + j, fx, fy, fz);
        for (int k = 0; k < entryCount; ++k)
        {
            fx += source[k].sign * source[k].x[j];
            fy += source[k].sign * source[k].x[source[k].stride + j];
            fz += source[k].sign * source[k].x[2 * source[k].stride + j];
        }
        finishMass<config>(args, state, first + j, local + j, fx, fy, fz);
    }
}

/// The same sums for a pattern of any length, mass by mass.
template <PassConfig config>
[[gnu::always_inline]] inline void entryByEntry(const SpringRowPlan::MassRun& run, const SpringRowPlan::Entry* entries,
                                                const RowForces& previous, const RowForces& current,
                                                const BandedForceArgs& args, const BandState& state)
{
    for (std::size_t j = 0; j < run.count; ++j)
    {
        Real fx;
        Real fy;
        Real fz;
        ownForce<config>(args, state, run.firstMass + j, run.local + j, fx, fy, fz);
        for (Index k = 0; k < run.entryCount; ++k)
        {
            const EntrySource source = entrySource(entries[run.firstEntry + k], previous, current);
            fx += source.sign * source.x[j];
            fy += source.sign * source.x[source.stride + j];
            fz += source.sign * source.x[2 * source.stride + j];
        }
        finishMass<config>(args, state, run.firstMass + j, run.local + j, fx, fy, fz);
    }
}

/// Dispatches a mass run to the fused loop of its entry count.
template <PassConfig config, int entryCount = 1>
[[gnu::always_inline]] inline void massRun(const SpringRowPlan::MassRun& run, const SpringRowPlan::Entry* entries,
                                           const RowForces& previous, const RowForces& current,
                                           const BandedForceArgs& args, const BandState& state)
{
    if constexpr (entryCount > maxFusedEntries)
    {
        entryByEntry<config>(run, entries, previous, current, args, state);
    }
    else if (run.entryCount == Index(entryCount))
    {
        fusedMassRun<config, entryCount>(run, entries, previous, current, args, state);
    }
    else
    {
        massRun<config, entryCount + 1>(run, entries, previous, current, args, state);
    }
}

/// Where the row before each band keeps its spring forces: band k's at boundary + boundaryOffset[k].
struct Boundaries
{
    Real* boundary = nullptr;
    const std::size_t* offset = nullptr;

    RowForces before(const SpringRowPlan& plan, std::size_t band) const
    {
        return {boundary + offset[band], plan.slotCount[band * plan.bandRows - 1]};
    }
};

/// One band: its masses' state copied, then row by row the row's springs and the row's masses. `scratch` holds the
/// copy and two spring rows.
template <PassConfig config, bool withRepulsion>
[[gnu::always_inline]] inline void bandBody(const BandedForceArgs& args, const Boundaries& boundaries, std::size_t band,
                                            Real* scratch)
{
    const SpringRowPlan& plan = *args.plan;
    const std::size_t stride = plan.largestBandMassCount;
    const BandState state{scratch, scratch + 3 * stride, stride};
    for (Index k = plan.bandRangeStart[band]; k < plan.bandRangeStart[band + 1]; ++k)
    {
        const SpringRowPlan::MassRange& range = plan.bandRanges[k];
        splitComponents(range.count, args.x[range.firstMass].data(), state.position + range.local, stride);
        splitComponents(range.count, args.v[range.firstMass].data(), state.velocity + range.local, stride);
    }
    Real* rowScratch = scratch + 6 * stride;
    const std::size_t slots = plan.largestSlotCount;
    const std::size_t begin = band * plan.bandRows;
    const std::size_t end = std::min(plan.rowCount, begin + plan.bandRows);
    RowForces previous;
    if (band > 0)
    {
        previous = boundaries.before(plan, band);
    }
    for (std::size_t row = begin; row < end; ++row)
    {
        RowForces current;
        if (row + 1 == end && end < plan.rowCount)
        {
            current = boundaries.before(plan, band + 1);
        }
        else
        {
            current = {rowScratch + (row % 2) * 3 * slots, slots};
            springRowFromBand<withRepulsion>(plan, args, row, state, current);
        }
        for (Index k = plan.massRunStart[row]; k < plan.massRunStart[row + 1]; ++k)
        {
            massRun<config>(plan.massRuns[k], plan.entries.data(), previous, current, args, state);
        }
        previous = current;
    }
}

/// The rows before bands [firstBand, endBand), into the boundary buffer.
template <bool withRepulsion>
[[gnu::always_inline]] inline void boundaryBody(const BandedForceArgs& args, const Boundaries& boundaries,
                                                std::size_t firstBand, std::size_t endBand)
{
    const SpringRowPlan& plan = *args.plan;
    for (std::size_t band = firstBand; band < endBand; ++band)
    {
        springRowFromArrays<withRepulsion>(plan, args, band * plan.bandRows - 1, boundaries.before(plan, band));
    }
}

// One copy of each kernel per SIMD path: only the instruction set differs (see SimdPath.h for why the bits do not).
#define MASSE_BAND_KERNELS(suffix, targetAttribute)                                                                    \
    template <PassConfig config, bool withRepulsion>                                                                   \
    targetAttribute void band##suffix(const BandedForceArgs& args, const Boundaries& boundaries, std::size_t band,     \
                                      Real* scratch)                                                                   \
    {                                                                                                                  \
        bandBody<config, withRepulsion>(args, boundaries, band, scratch);                                              \
    }                                                                                                                  \
    template <bool withRepulsion>                                                                                      \
    targetAttribute void boundary##suffix(const BandedForceArgs& args, const Boundaries& boundaries,                   \
                                          std::size_t firstBand, std::size_t endBand)                                  \
    {                                                                                                                  \
        boundaryBody<withRepulsion>(args, boundaries, firstBand, endBand);                                             \
    }

MASSE_BAND_KERNELS(Default, )
#if defined(__x86_64__) && defined(__GNUC__)
MASSE_BAND_KERNELS(Avx2, __attribute__((target("avx2"))))
MASSE_BAND_KERNELS(Avx512, __attribute__((target("avx512f"))))
#endif
#undef MASSE_BAND_KERNELS

template <PassConfig config, bool withRepulsion>
void bandOn(SimdPath path, const BandedForceArgs& args, const Boundaries& boundaries, std::size_t band, Real* scratch)
{
    switch (path)
    {
#if defined(__x86_64__) && defined(__GNUC__)
    case SimdPath::Avx512:
        return bandAvx512<config, withRepulsion>(args, boundaries, band, scratch);
    case SimdPath::Avx2:
        return bandAvx2<config, withRepulsion>(args, boundaries, band, scratch);
#endif
    default:
        return bandDefault<config, withRepulsion>(args, boundaries, band, scratch);
    }
}

template <bool withRepulsion>
void boundaryOn(SimdPath path, const BandedForceArgs& args, const Boundaries& boundaries, std::size_t firstBand,
                std::size_t endBand)
{
    switch (path)
    {
#if defined(__x86_64__) && defined(__GNUC__)
    case SimdPath::Avx512:
        return boundaryAvx512<withRepulsion>(args, boundaries, firstBand, endBand);
    case SimdPath::Avx2:
        return boundaryAvx2<withRepulsion>(args, boundaries, firstBand, endBand);
#endif
    default:
        return boundaryDefault<withRepulsion>(args, boundaries, firstBand, endBand);
    }
}

template <PassConfig config> void runBands(const BandedForceArgs& args)
{
    const SpringRowPlan& plan = *args.plan;
    const std::size_t bands = plan.bandCount();
    // The rows between bands, kept by the calling thread from call to call (no allocation per substep).
    thread_local std::vector<Real> boundary;
    thread_local std::vector<std::size_t> offset;
    offset.assign(bands + 1, 0);
    for (std::size_t band = 1; band < bands; ++band)
    {
        offset[band + 1] = offset[band] + 3 * std::size_t(plan.slotCount[band * plan.bandRows - 1]);
    }
    if (boundary.size() < offset[bands])
    {
        boundary.resize(offset[bands]);
    }
    const Boundaries boundaries{boundary.data(), offset.data()};
    const SimdPath path = activeSimdPath();
    const bool repulsion = args.repulsion > 0;
    // A few boundary rows a chunk: each is one row of springs, too little to wake a thread for alone.
    constexpr std::size_t boundaryChunk = 4;
    if (bands > 1)
    {
        parallelFor(bands - 1, boundaryChunk,
                    [&](std::size_t begin, std::size_t end)
                    {
                        repulsion ? boundaryOn<true>(path, args, boundaries, begin + 1, end + 1)
                                  : boundaryOn<false>(path, args, boundaries, begin + 1, end + 1);
                    });
    }
    const std::size_t scratchSize = 6 * plan.largestBandMassCount + 2 * 3 * plan.largestSlotCount;
    parallelFor(bands, 1,
                [&](std::size_t begin, std::size_t end)
                {
                    // Each thread's band copy and two spring rows, kept from call to call.
                    thread_local std::vector<Real> scratch;
                    if (scratch.size() < scratchSize)
                    {
                        scratch.resize(scratchSize);
                    }
                    for (std::size_t band = begin; band < end; ++band)
                    {
                        repulsion ? bandOn<config, true>(path, args, boundaries, band, scratch.data())
                                  : bandOn<config, false>(path, args, boundaries, band, scratch.data());
                    }
                });
}
} // namespace

void runBandedForces(BandedPass pass, const BandedForceArgs& args)
{
    const bool storeForce = args.force != nullptr;
    switch (pass)
    {
    case BandedPass::AddSpringForces:
        return runBands<PassConfig{BandedPass::AddSpringForces, true}>(args);
    case BandedPass::TotalForces:
        return runBands<PassConfig{BandedPass::TotalForces, true}>(args);
    case BandedPass::SymplecticSubstep:
        return storeForce ? runBands<PassConfig{BandedPass::SymplecticSubstep, true}>(args)
                          : runBands<PassConfig{BandedPass::SymplecticSubstep, false}>(args);
    case BandedPass::SymplecticSubstepWithoutExternalForces:
        return storeForce ? runBands<PassConfig{BandedPass::SymplecticSubstepWithoutExternalForces, true}>(args)
                          : runBands<PassConfig{BandedPass::SymplecticSubstepWithoutExternalForces, false}>(args);
    }
}
} // namespace masse
