#include "core/contact/SelfContact.h"

#include "core/Format.h"
#include "core/InputError.h"
#include "core/contact/ClosestPointOnTriangle.h"
#include "core/parallel/TaskPool.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace masse
{
namespace
{
/// Pairs per range of the substep's detection: enough work to pay for waking a thread.
constexpr std::size_t selfPairChunkSize = 2048;
static_assert(selfPairChunkSize % 64 == 0, "a range of pairs starts on a word of the pass's bitmap");
/// Passes of detection and responses after an implicit integrator's step, at most (see afterImplicitSolve).
constexpr int selfResponsePasses = 128;
/// With one solve a frame: the most a pair may close in one solve, in lattice spacings, before the frame is split
/// (solvesFor).
constexpr Real closingPerSolve = 6;
/// The most solves a frame is split into.
constexpr int maxSolvesAFrame = 8;
/// Vertices whose pairs at rest are sought at once while the exclusions are listed: few enough that their pairs
/// (about 4 (3 radius / spacing)^2 each, held twice) stay below the lists they leave, and enough that the
/// broadphase's refit of the whole sheet before each batch (4 ms at 128x2x128) is paid only a few times.
constexpr std::size_t exclusionBatchSize = 4096;

/// Per mass, its list of triangles sorted and made unique, laid out one after another (the lists are emptied).
SelfContactExclusions exclusionsOf(std::vector<std::vector<Index>>& lists)
{
    SelfContactExclusions out;
    out.start.assign(lists.size() + 1, 0);
    for (std::size_t i = 0; i < lists.size(); ++i)
    {
        std::vector<Index>& list = lists[i];
        std::sort(list.begin(), list.end());
        list.erase(std::unique(list.begin(), list.end()), list.end());
        out.triangles.insert(out.triangles.end(), list.begin(), list.end());
        out.start[i + 1] = out.triangles.size();
        std::vector<Index>().swap(list);
    }
    return out;
}
} // namespace

void validate(const SelfContactSettings& settings)
{
    if (!(settings.radius > 0) || !std::isfinite(settings.radius))
    {
        throw InputError("radius", "must be a positive number of metres (got " + formatNumber(settings.radius) + ")");
    }
    if (!(settings.friction >= 0) || !std::isfinite(settings.friction))
    {
        throw InputError("friction", "must be >= 0 (got " + formatNumber(settings.friction) + ")");
    }
}

SelfContact::SelfContact(const Lattice& lattice, SelfContactBroadphase& broadphase, const SelfContactSettings& settings,
                         Exclusions exclusions)
    : m_broadphase(broadphase), m_settings(settings)
{
    validate(settings);
    SheetSurface surface = sheetSurface(lattice);
    m_triangles = std::move(surface.triangles);
    m_vertices = std::move(surface.vertices);

    const std::size_t n = lattice.massCount();
    m_skin.assign(n, 0);
    m_listedAt.assign(n, Vec3::Zero());
    m_restPosition = lattice.position;
    const Real spacing = lattice.smallerSpacing();
    m_spacing = spacing > 0 ? spacing : m_settings.radius; // a lattice one mass wide has no spacing along that side
    m_triangleLow.resize(m_triangles.size());
    m_triangleHigh.resize(m_triangles.size());
    m_triangleMotionLow.resize(m_triangles.size());
    m_triangleMotionHigh.resize(m_triangles.size());
    m_lastVelocity.assign(n, Vec3::Zero());
    m_moved.has.assign(n, 0);
    m_pushed.has.assign(n, 0);
    m_waiting.has.assign(n, 0);
    listTrianglesOfMasses(n);
    m_broadphase.setTriangles(m_triangles);
    listSpringExclusions(lattice.springs.adjacency(n)); // the lattice's springs, not kept: the hook holds nothing of it
    if (exclusions == Exclusions::Listed)
    {
        listRestExclusions();
    }
}

void SelfContact::listSpringExclusions(const SpringAdjacency& springsAt)
{
    const std::size_t n = m_restPosition.size();
    std::vector<std::vector<Index>> excluded(n);
    std::vector<std::uint8_t> onSurface(n, 0);
    for (const Index v : m_vertices)
    {
        onSurface[v] = 1;
    }
    // A triangle holding the vertex, or one of its spring neighbours: the springs hold those apart. The adjacency is
    // symmetric, so the triangle is listed for its masses and each of their neighbours.
    for (std::size_t k = 0; k < m_triangles.size(); ++k)
    {
        for (const Index m : m_triangles[k])
        {
            excluded[m].push_back(Index(k));
            for (std::size_t e = springsAt.offsets[m]; e < springsAt.offsets[m + 1]; ++e)
            {
                if (onSurface[springsAt.entries[e].other])
                {
                    excluded[springsAt.entries[e].other].push_back(Index(k));
                }
            }
        }
    }
    m_excluded = exclusionsOf(excluded);
    m_restExcluded = false;
}

bool SelfContact::nearAtRest(Index v, Index k) const
{
    const Triangle& t = m_triangles[k];
    const std::vector<Vec3>& x = m_restPosition;
    return (x[v] - closestPointOnTriangle(x[v], x[t[0]], x[t[1]], x[t[2]])).squaredNorm() <
           4 * m_settings.radius * m_settings.radius;
}

void SelfContact::listRestExclusions()
{
    if (m_restExcluded)
    {
        return;
    }
    // Every pair within twice the radius at rest is among the broadphase's pairs for the rest positions with a skin of
    // one radius (their boxes are then within three radii); the exact test sorts them out once, instead of at every
    // list. The pairs are sought for a batch of vertices at a time: each vertex's pairs do not depend on the others
    // asked with it, and the broadphase's pairs of the whole sheet at once (about (3 radius / spacing)^2 per vertex,
    // kept twice) would be the largest allocation of a run on a fine lattice. The springs' exclusions are in place
    // while they are sought: those pairs would be excluded anyway.
    const std::size_t n = m_restPosition.size();
    std::vector<std::vector<Index>> near(n);
    std::fill(m_skin.begin(), m_skin.end(), m_settings.radius);
    std::vector<Index> batch;
    for (std::size_t first = 0; first < m_vertices.size(); first += exclusionBatchSize)
    {
        const auto from = m_vertices.begin() + std::ptrdiff_t(first);
        batch.assign(from, from + std::ptrdiff_t(std::min(exclusionBatchSize, m_vertices.size() - first)));
        m_broadphase.findPairs(m_restPosition, m_skin, m_settings.radius, batch, m_excluded, m_pairs);
        for (const SelfContactPair& pair : m_pairs)
        {
            if (nearAtRest(pair.vertex, pair.triangle))
            {
                near[pair.vertex].push_back(pair.triangle);
            }
        }
    }
    std::vector<SelfContactPair>().swap(m_pairs);
    // Each mass's list: those near at rest and its springs' exclusions.
    for (std::size_t i = 0; i < n; ++i)
    {
        near[i].insert(near[i].end(), m_excluded.triangles.begin() + std::ptrdiff_t(m_excluded.start[i]),
                       m_excluded.triangles.begin() + std::ptrdiff_t(m_excluded.start[i + 1]));
    }
    m_excluded = exclusionsOf(near);
    m_restExcluded = true;
}

void SelfContact::beginFrame(MassSpringSystem& system, StepContext& context, Real /*time*/, Real dt)
{
    const StageScope stage(m_observer, Stage::SelfContactPairs);
    const Particles& p = system.particles;
    if (m_oneSolveAFrame)
    {
        if (!preparedFor(p, dt))
        {
            listSweptPairs(p, dt);
            weighArrivals(p, dt);
        }
        m_prepared = false;
        for (const Index i : m_vertices)
        {
            m_lastVelocity[i] = p.velocity[i];
        }
        m_substepStart = p.position;
        m_report.lastFrame = 0;
        constrainArrivals(p, context.constraints);
        return;
    }
    // With the explicit integrators, each mass's skin for this frame: how far it may move relative to the surface's
    // mean motion before the pairs are listed again, twice what its velocity and the change of its velocity over the
    // last frame (its observed acceleration, the contact's and the springs' included) relative to the surface's mean
    // would carry it, and at least a quarter radius. Relative to the mean, because a pair's distance does not change
    // when the whole sheet moves: a falling sheet needs no more pairs than a resting one. Not the force of the last
    // evaluation: a mass resting on an obstacle carries the springs' and gravity's pull that the contact cancels. At
    // most the radius: two halves of a fold swinging past each other at metres per second would otherwise list every
    // pair within a frame's swing (millions on a 48x2x48 sheet); with the cap they are listed again every few
    // substeps while they move that fast.
    Vec3 meanVelocity = Vec3::Zero();
    Vec3 meanChange = Vec3::Zero();
    for (const Index i : m_vertices)
    {
        meanVelocity += p.velocity[i];
        meanChange += p.velocity[i] - m_lastVelocity[i];
    }
    meanVelocity /= Real(m_vertices.size());
    meanChange /= Real(m_vertices.size());
    for (const Index i : m_vertices)
    {
        const Real speed = (p.velocity[i] - meanVelocity).norm();
        const Real change = (p.velocity[i] - m_lastVelocity[i] - meanChange).norm();
        m_skin[i] = std::min(2 * (speed + change) * dt + Real(0.25) * m_settings.radius, m_settings.radius);
        m_lastVelocity[i] = p.velocity[i];
    }
    listPairs(p.position);
    m_substepStart = p.position;
    m_report.lastFrame = 0;
}

void SelfContact::listSweptPairs(const Particles& p, Real dt)
{
    // One solve takes the frame: the pairs are the ones that may meet during it, each mass moving from where it is
    // along its velocity and the surface's mean change of velocity over the last frame, within twice its own
    // change's difference from that mean plus a quarter radius (swept boxes, not spheres about each mass: two
    // halves of a fold swinging towards each other at metres per second come centimetres closer in a step, more than a
    // skin capped at the radius covers, and with such a skin they would cross each other unseen by the constraints; the
    // 96x2x96 fold would then diverge where they meet, pushed back by up to 6.5 cm after the solve). The constraints
    // are then set from the present velocities: set from the velocities plus their last change (backward Euler moves a
    // mass by its velocity at the step's end), the 64x2x64 fold diverges where its halves meet.
    Vec3 meanChange = Vec3::Zero();
    for (const Index i : m_vertices)
    {
        meanChange += p.velocity[i] - m_lastVelocity[i];
    }
    meanChange /= Real(m_vertices.size());
    m_sweptEnd.resize(p.size());
    for (const Index i : m_vertices)
    {
        const Vec3 change = p.velocity[i] - m_lastVelocity[i];
        m_skin[i] = 2 * (change - meanChange).norm() * dt + Real(0.25) * m_settings.radius;
        m_sweptEnd[i] = p.position[i] + (p.velocity[i] + meanChange) * dt;
    }
    // Only the pairs the arrivals may take are kept (weighArrival turns the others away by the same test): most
    // pairs of the swept boxes are neighbours moving together, 14 to 17 million a frame once the 128x2x128 fold lies
    // on the rod.
    m_broadphase.findSweptArrivingPairs(p.position, m_sweptEnd, m_skin, m_settings.radius, m_vertices, m_excluded,
                                        arrivalTest(p, dt), m_pairs);
    pairsListed(p.position);
}

ArrivalTest SelfContact::arrivalTest(const Particles& p, Real dt) const
{
    ArrivalTest test;
    test.velocity = &p.velocity;
    test.dt = dt;
    test.rest = Real(0.25) * m_settings.radius;
    test.slack = Real(1e-6) * m_settings.radius;
    return test;
}

bool SelfContact::preparedFor(const Particles& p, Real dt) const
{
    return m_prepared && m_preparedDt == dt && m_preparedPosition == p.position && m_preparedVelocity == p.velocity;
}

int SelfContact::solvesFor(MassSpringSystem& system, Real dt)
{
    listRestExclusions(); // once, for a self-contact made with SpringsOnly that runs frames after all
    // The frame's pairs are listed and weighed now, as beginFrame would (it keeps them unless a stage before it has
    // moved a mass), and the frame is split when some pair would close by more than closingPerSolve lattice spacings
    // in one solve: the constraints are set once a solve, along each pair's normal at its start, and where a fold
    // meets faster the sheet between crumples through itself within the solve. Unsplit, the 128x2x128 fold over the rod
    // at dt 0.03 diverges so at 0.63 s, its fastest pair closing 15 spacings (12 cm) in one solve; at dt 0.015 it runs,
    // and so does the 64x2x64 fold at dt 0.03 (7.7 spacings). With the split at 6, the 128x2x128 fold runs its 3 s in
    // 105 solves for 100 frames, the 64x2x64 one in 101; the 16x2x16 fold and the wrap never split.
    const StageScope stage(m_observer, Stage::SelfContactPairs);
    const Particles& p = system.particles;
    listSweptPairs(p, dt);
    const Real closing = weighArrivals(p, dt);
    m_prepared = true;
    m_preparedDt = dt;
    m_preparedPosition = p.position;
    m_preparedVelocity = p.velocity;
    const Real solves = std::ceil(closing / (closingPerSolve * m_spacing));
    return solves > 1 ? int(std::min(solves, Real(maxSolvesAFrame))) : 1;
}

Real SelfContact::weighArrivals(const Particles& p, Real dt)
{
    measureTriangleBoxes(p.position, false); // for weighArrival's first test
    m_arrival.assign(p.size(), Arrival{});
    m_leaving.resize(p.size(), 0);
    // Over ranges of pairs on every thread: the pairs come by vertex, and each range takes the vertices whose first
    // pair lies in it, whole, so each vertex's pairs are weighed on one thread in pair order. The fastest closing is
    // each range's maximum and then theirs: a maximum does not depend on the order it is taken in.
    const std::size_t count = m_pairs.size();
    const auto runStart = [&](std::size_t k)
    {
        while (k > 0 && k < count && m_pairs[k].vertex == m_pairs[k - 1].vertex)
        {
            ++k;
        }
        return k;
    };
    m_rangeClosing.assign(chunkCount(count, selfPairChunkSize), 0);
    const ArrivalTest test = arrivalTest(p, dt);
    parallelFor(count, selfPairChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    Real closing = 0;
                    const std::size_t last = runStart(end);
                    for (std::size_t k = runStart(begin); k < last; ++k)
                    {
                        closing = std::max(closing, weighArrival(p, test, m_pairs[k]));
                    }
                    m_rangeClosing[begin / selfPairChunkSize] = closing;
                });
    Real closing = 0;
    for (const Real c : m_rangeClosing)
    {
        closing = std::max(closing, c);
    }
    return closing;
}

void SelfContact::constrainArrivals(const Particles& p, std::vector<VelocityConstraint>& constraints)
{
    // A pair that the frame's step would carry within the radius is stopped inside the solve, where the springs
    // behind its masses are stopped with them; the responses after the solve only correct what is left. Stopped after
    // the solve alone, the 48x2x48 fold over the rod would have its meeting layers pushed back by centimetres while the
    // layers behind them move on, and the springs between would take 24 J in two steps. Each surface vertex is
    // constrained by its most urgent pair (the one its step would carry deepest, the first in pair order on a tie: the
    // same at any thread count), unless the obstacle contact holds it or it is pinned; the triangle's masses are
    // vertices of their own pairs across the fold, so both sides are stopped.
    const std::vector<Vec3>& v = p.velocity;
    m_constraints.clear();
    for (const VelocityConstraint& c : constraints)
    {
        Arrival& arrival = m_arrival[c.mass];
        arrival.held = true;
        arrival.heldAlong = c.directions == 1 ? c.normal : Vec3(Vec3::Zero());
    }
    // A mass the obstacle contact holds along one normal is constrained along its pair's normal too when the two are
    // far from parallel: a strip's end pulled round an obstacle's corner into a fold of its own sheet rests on the
    // obstacle's face and meets the fold's side; left to the responses after the solve, the solve carries it through
    // the fold (5.5 cm in one frame of the wrap), and the responses and the obstacle's projection push it back and
    // forth between them. Normals closer than about 73 degrees are left to the obstacle: two constraints that close
    // leave the mass little room to slide along the obstacle, and the fold over the rod then has 27% of its left half
    // beyond its mirror (4.7% this way) with a bound of 0.5 on the cosine.
    constexpr Real parallelCosine = Real(0.3);
    for (const Index i : m_vertices)
    {
        const Arrival& arrival = m_arrival[i];
        const bool alongAnother = arrival.held && (arrival.heldAlong.isZero() ||
                                                   std::abs(arrival.heldAlong.dot(arrival.normal)) > parallelCosine);
        if (alongAnother || p.pinned[i] || !(arrival.endGap < 0))
        {
            continue;
        }
        VelocityConstraint c;
        c.mass = i;
        c.normal = arrival.normal;
        c.velocity = v[i] + (arrival.speed - arrival.normal.dot(v[i])) * arrival.normal;
        m_constraints.emplace_back(i, constraints.size());
        constraints.push_back(c);
    }
}

Real SelfContact::weighArrival(const Particles& p, const ArrivalTest& test, const SelfContactPair& pair)
{
    Arrival& arrival = m_arrival[pair.vertex];
    const std::vector<Vec3>& x = p.position;
    const std::vector<Vec3>& v = p.velocity;
    const Real dt = test.dt;
    const Triangle& t = m_triangles[pair.triangle];
    // A pair whose vertex is more than a quarter radius from touching the triangle's box and farther than the step's
    // relative motion (the triangle's point moves as a weighted mean of its masses, so the pair closes at most as
    // fast as the vertex moves towards the fastest of them) cannot arrive, and its closest point need not be sought.
    // The broadphase's list leaves out such pairs already (findSweptArrivingPairs); the test here keeps the
    // weighing the same whatever a broadphase lists.
    const Real boxGap =
        gapToBox(x[pair.vertex], m_triangleLow[pair.triangle], m_triangleHigh[pair.triangle], m_settings.radius);
    if (!test.mayArrive(boxGap, test.relativeSpeed(pair.vertex, t)))
    {
        return 0;
    }
    const Vec3 w = closestPointWeights(x[pair.vertex], x[t[0]], x[t[1]], x[t[2]]);
    Vec3 normal = x[pair.vertex] - (w[0] * x[t[0]] + w[1] * x[t[1]] + w[2] * x[t[2]]);
    const Real distance = normal.norm();
    if (!(distance > Real(1e-9) * m_settings.radius))
    {
        return 0; // no direction to part along; the responses after the solve take it
    }
    normal /= distance;
    const Real vertexSpeed = normal.dot(v[pair.vertex]);
    const Real triangleSpeed = normal.dot(w[0] * v[t[0]] + w[1] * v[t[1]] + w[2] * v[t[2]]);
    const Real gap = distance - m_settings.radius;
    // At the present speeds; a pair resting within a quarter radius of touching counts as arriving unless its
    // vertex was leaving, so that the step's forces cannot press it in.
    const bool resting = gap < Real(0.25) * m_settings.radius && !m_leaving[pair.vertex];
    const Real closes = dt * (triangleSpeed - vertexSpeed);
    const Real closing = gap < closes ? closes : 0;
    const Real endGap = std::min(gap - closes, resting ? Real(-1e-12) : Real(0));
    if (endGap >= 0 || endGap >= arrival.endGap)
    {
        return closing;
    }
    // Inelastic: the vertex takes the pair's common normal speed (the vertex and the triangle's point weighted
    // by their masses), plus its share of what closes the gap to the radius (or opens it, if already inside).
    const Real vertexInverse = p.inverseMass[pair.vertex];
    const Real triangleInverse =
        w[0] * w[0] * p.inverseMass[t[0]] + w[1] * w[1] * p.inverseMass[t[1]] + w[2] * w[2] * p.inverseMass[t[2]];
    const Real inverseSum = vertexInverse + triangleInverse;
    if (!(inverseSum > 0))
    {
        return closing; // all four pinned
    }
    const Real common = (triangleInverse * vertexSpeed + vertexInverse * triangleSpeed) / inverseSum;
    arrival.endGap = endGap;
    arrival.normal = normal;
    arrival.speed = common + (vertexInverse / inverseSum) * (-gap / dt);
    return closing;
}

void SelfContact::listPairs(const std::vector<Vec3>& x)
{
    // The broadphase keeps only the pairs within the radius plus their two skins: one farther apart cannot touch
    // while the list stands (the closest point of the triangle moves less than the farthest of its masses, relative
    // to the surface's mean motion), so no substep's detection tests it.
    m_broadphase.findPairs(x, m_skin, m_settings.radius, m_vertices, m_excluded, m_pairs);
    pairsListed(x);
}

void SelfContact::pairsListed(const std::vector<Vec3>& x)
{
    for (const Index i : m_vertices)
    {
        m_listedAt[i] = x[i];
    }
    // Each range's list can hold every pair of its range, so the substeps never allocate.
    const std::size_t ranges = chunkCount(m_pairs.size(), selfPairChunkSize);
    m_touches.reserveChunks(ranges);
    for (std::size_t range = 0; range < m_touches.size(); ++range)
    {
        m_touches[range].clear(); // they name pairs of the old list
        m_touches[range].reserve(selfPairChunkSize);
    }
    m_pairsIndexed = false;
    m_report.pairs = m_pairs.size();
    ++m_report.queries;
}

void SelfContact::pairsWithin(const std::vector<Vec3>& x, Real distance, std::vector<SelfContactPair>& out)
{
    // No reach: the broadphase lists exactly the pairs closer than the distance.
    const std::vector<Real> noReach(x.size(), 0);
    m_broadphase.findPairs(x, noReach, distance, m_vertices, m_excluded, out);
    if (!m_restExcluded)
    {
        // The pairs the rest exclusions would have left: the broadphase's walk skips an excluded pair and keeps the
        // others in its order.
        std::erase_if(out, [&](const SelfContactPair& pair) { return nearAtRest(pair.vertex, pair.triangle); });
    }
}

void SelfContact::markTouchingMasses(std::vector<std::uint8_t>& flags) const
{
    const std::size_t ranges = chunkCount(m_pairs.size(), selfPairChunkSize);
    for (std::size_t range = 0; range < ranges && range < m_touches.size(); ++range)
    {
        for (const Touch& touch : m_touches[range])
        {
            const SelfContactPair& pair = m_pairs[touch.pair];
            flags[pair.vertex] = 1;
            for (const Index i : m_triangles[pair.triangle])
            {
                flags[i] = 1;
            }
        }
    }
}

bool SelfContact::outgrewPairs(const std::vector<Vec3>& x) const
{
    // The list holds every pair within the radius plus the two skins when it was made; it stays complete while each
    // mass has moved less than its skin relative to the surface's mean displacement.
    Vec3 mean = Vec3::Zero();
    for (const Index i : m_vertices)
    {
        mean += x[i] - m_listedAt[i];
    }
    mean /= Real(m_vertices.size());
    for (const Index i : m_vertices)
    {
        if ((x[i] - m_listedAt[i] - mean).squaredNorm() >= m_skin[i] * m_skin[i])
        {
            return true;
        }
    }
    return false;
}

void SelfContact::detectPair(const std::vector<Vec3>& x, std::size_t k, std::vector<Touch>& out) const
{
    const Real radius = m_settings.radius;
    const SelfContactPair& pair = m_pairs[k];
    const Vec3& v = x[pair.vertex];
    // Most listed pairs are a skin away: the triangle's box, grown by the radius, turns them away with six
    // comparisons before the closest point is sought.
    const Vec3& low = m_triangleLow[pair.triangle];
    const Vec3& high = m_triangleHigh[pair.triangle];
    const auto outsideBox = [&](Real grown)
    {
        return v.x() < low.x() - grown || v.y() < low.y() - grown || v.z() < low.z() - grown ||
               v.x() > high.x() + grown || v.y() > high.y() + grown || v.z() > high.z() + grown;
    };
    Touch touch{std::uint32_t(k), Vec3::Zero()};
    if (outsideBox(radius))
    {
        // Passing through needs the vertex within the radius of the triangle at some moment of the substep. In the
        // vertex's frame each of the triangle's masses has moved by its own displacement less the vertex's, so the
        // vertex must now be within the radius plus the most of those along any axis of the triangle's box. Most
        // listed pairs are not: neighbours in a sheet that moves as one, however fast. A billionth of the radius to
        // spare, so that rounding never turns away a pair the swept test would take.
        const Vec3 vertexMoved = v - m_substepStart[pair.vertex];
        const Real relativeMotion = (m_triangleMotionHigh[pair.triangle] - vertexMoved)
                                        .cwiseMax(vertexMoved - m_triangleMotionLow[pair.triangle])
                                        .maxCoeff();
        const Real reach = radius + relativeMotion + Real(1e-9) * radius;
        if (!outsideBox(reach) && crossed(x, k, touch))
        {
            out.push_back(touch);
        }
        return;
    }
    const Triangle& t = m_triangles[pair.triangle];
    const Vec3 weights = closestPointWeights(v, x[t[0]], x[t[1]], x[t[2]]);
    const Vec3 closest = weights[0] * x[t[0]] + weights[1] * x[t[1]] + weights[2] * x[t[2]];
    if ((v - closest).squaredNorm() < radius * radius)
    {
        touch.weights = weights;
        out.push_back(touch);
    }
    else if (crossed(x, k, touch))
    {
        out.push_back(touch);
    }
}

bool SelfContact::crossed(const std::vector<Vec3>& x, std::size_t k, Touch& touch) const
{
    const SelfContactPair& pair = m_pairs[k];
    const Triangle& t = m_triangles[pair.triangle];
    const std::vector<Vec3>& x0 = m_substepStart;
    // The vertex's height over the triangle's plane (times twice its area) at the substep's start and end: a
    // crossing changes its sign.
    const Vec3 normalBefore = (x0[t[1]] - x0[t[0]]).cross(x0[t[2]] - x0[t[0]]);
    const Vec3 normalAfter = (x[t[1]] - x[t[0]]).cross(x[t[2]] - x[t[0]]);
    const Real before = normalBefore.dot(x0[pair.vertex] - x0[t[0]]);
    const Real after = normalAfter.dot(x[pair.vertex] - x[t[0]]);
    if (!(before > 0 && after < 0) && !(before < 0 && after > 0))
    {
        return false;
    }
    // Where the height passed zero, all four masses taken along straight lines (exact for a triangle that only
    // translates; near enough over one substep otherwise): the crossing counts if it was through the triangle, its
    // closest point there strictly inside (not on an edge) and within the radius. A vertex that only grazes the
    // plane beside an edge, as one of a fold's crease does, has not passed through; where it crossed next to the
    // edge inside the sheet, the triangle across that edge has it inside.
    const Real s = before / (before - after);
    const auto at = [&](Index i) { return Vec3(x0[i] + s * (x[i] - x0[i])); };
    const Vec3 vertex = at(pair.vertex);
    const Vec3 a = at(t[0]);
    const Vec3 b = at(t[1]);
    const Vec3 c = at(t[2]);
    const Vec3 weights = closestPointWeights(vertex, a, b, c);
    const Vec3 closest = weights[0] * a + weights[1] * b + weights[2] * c;
    if (!(weights[0] > 0 && weights[1] > 0 && weights[2] > 0) ||
        !((vertex - closest).squaredNorm() < m_settings.radius * m_settings.radius))
    {
        return false;
    }
    touch.weights = weights;
    touch.side = before > 0 ? Real(1) : Real(-1);
    return true;
}

SelfContact::Responded SelfContact::respond(Particles& p, const Touch& touch, Real h) const
{
    const SelfContactPair& pair = m_pairs[touch.pair];
    const Triangle& t = m_triangles[pair.triangle];
    const Index v = pair.vertex;
    const Vec3& w = touch.weights;
    // The generalised inverse mass of the pair's relative motion: an impulse J on the vertex and -w_k J on the
    // triangle's masses changes their relative velocity by this times J.
    const Real inverseMass = p.inverseMass[v] + w[0] * w[0] * p.inverseMass[t[0]] + w[1] * w[1] * p.inverseMass[t[1]] +
                             w[2] * w[2] * p.inverseMass[t[2]];
    if (!(inverseMass > 0))
    {
        return {}; // all four pinned
    }
    // Measured again here: an earlier response in this pass may have moved these masses.
    const Vec3 closest = w[0] * p.position[t[0]] + w[1] * p.position[t[1]] + w[2] * p.position[t[2]];
    Vec3 normal = p.position[v] - closest;
    Real distance = normal.norm();
    if (touch.side != 0)
    {
        // Passed through: back to the side it came from, along the face normal; its height over the triangle on
        // that side is negative (or below the radius, if an earlier response has already moved it).
        normal = touch.side * (p.position[t[1]] - p.position[t[0]]).cross(p.position[t[2]] - p.position[t[0]]);
        const Real length = normal.norm();
        if (!(length > 0))
        {
            return {};
        }
        normal /= length;
        distance = normal.dot(p.position[v] - closest);
        if (distance >= m_settings.radius)
        {
            return {};
        }
    }
    else if (distance >= m_settings.radius)
    {
        return {};
    }
    else if (distance > Real(1e-9) * m_settings.radius)
    {
        normal /= distance;
    }
    else
    {
        // On the triangle: push out along its face normal (either side is as good; this one is fixed).
        normal = (p.position[t[1]] - p.position[t[0]]).cross(p.position[t[2]] - p.position[t[0]]);
        const Real length = normal.norm();
        if (!(length > 0))
        {
            return {};
        }
        normal /= length;
    }
    const auto apply = [&](std::vector<Vec3>& field, const Vec3& change)
    {
        field[v] += p.inverseMass[v] * change;
        for (int k = 0; k < 3; ++k)
        {
            field[t[std::size_t(k)]] -= (w[k] * p.inverseMass[t[std::size_t(k)]]) * change;
        }
    };
    // Positions apart to the radius, shared so the masses' centre stays where it was.
    apply(p.position, ((m_settings.radius - distance) / inverseMass) * normal);

    const Vec3 relative = p.velocity[v] - (w[0] * p.velocity[t[0]] + w[1] * p.velocity[t[1]] + w[2] * p.velocity[t[2]]);
    const Real normalSpeed = relative.dot(normal);
    // Whether this response moved the pair by more than a thousandth of the radius (or stopped an approach that would
    // have, over the step): the passes after an implicit step go on until none does. A pair pushed apart by an
    // earlier pass is often found again a little inside the radius, its neighbours' pushes having moved it; with
    // rounding as the bound (a millionth of the radius) most frames of the 64x2x64 fold would take all 128 passes. With
    // this bound the halves keep the radius to 0.1% (SelfContactTest).
    const Real settled = Real(1e-3) * m_settings.radius;
    const bool moved = m_settings.radius - distance > settled || -normalSpeed * h > settled;
    // A mass's share of an impulse J moves it by at most the largest of these times J.
    const Real mostMoved = std::max(
        {p.inverseMass[v], w[0] * p.inverseMass[t[0]], w[1] * p.inverseMass[t[1]], w[2] * p.inverseMass[t[2]]});
    const Real pushImpulse = (m_settings.radius - distance) / inverseMass;
    if (normalSpeed >= 0)
    {
        return {moved, mostMoved * pushImpulse > settled}; // already parting
    }
    // Inelastic: the impulse that stops the approach. Friction: at most mu times it, and never more than stops the
    // sliding, so both only take kinetic energy away.
    const Real normalImpulse = -normalSpeed / inverseMass;
    const Vec3 tangential = relative - normalSpeed * normal;
    const Real slip = tangential.norm();
    Vec3 frictionImpulse = Vec3::Zero();
    if (slip > 0)
    {
        const Real magnitude = std::min(slip / inverseMass, m_settings.friction * normalImpulse);
        frictionImpulse = (-magnitude / slip) * tangential;
    }
    apply(p.velocity, normalImpulse * normal + frictionImpulse);
    // The integrator moved the masses with their velocities from before the impulse: move them by the friction's
    // change too, as the obstacle contact does, so a fold held by static friction does not creep.
    apply(p.position, h * frictionImpulse);
    return {moved, mostMoved * (pushImpulse + h * frictionImpulse.norm()) > settled};
}

void SelfContact::measureTriangleBoxes(const std::vector<Vec3>& x, bool withMotion)
{
    parallelFor(m_triangles.size(), selfPairChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    for (std::size_t k = begin; k < end; ++k)
                    {
                        measureTriangle(x, k, withMotion);
                    }
                });
}

void SelfContact::measureTriangle(const std::vector<Vec3>& x, std::size_t k, bool withMotion)
{
    const Triangle& t = m_triangles[k];
    m_triangleLow[k] = x[t[0]].cwiseMin(x[t[1]]).cwiseMin(x[t[2]]);
    m_triangleHigh[k] = x[t[0]].cwiseMax(x[t[1]]).cwiseMax(x[t[2]]);
    if (withMotion)
    {
        const Vec3 moved0 = x[t[0]] - m_substepStart[t[0]];
        const Vec3 moved1 = x[t[1]] - m_substepStart[t[1]];
        const Vec3 moved2 = x[t[2]] - m_substepStart[t[2]];
        m_triangleMotionLow[k] = moved0.cwiseMin(moved1).cwiseMin(moved2);
        m_triangleMotionHigh[k] = moved0.cwiseMax(moved1).cwiseMax(moved2);
    }
}

void SelfContact::afterSubstep(MassSpringSystem& system, StepContext& /*context*/, Real h, Real time)
{
    Particles& p = system.particles;
    if (m_oneSolveAFrame)
    {
        // The passes again, after the obstacle contact, which may have pushed a mass of a pair back towards the other
        // side (afterImplicitSolve runs them before it). Either order alone falls short: with the self-contact last,
        // the 64x2x64 fold's masses end frames 8.6 mm inside the rod; with the obstacles last, the wrap's flaps come to
        // 0.01 mm of each other and 11.7% of the 16x2x16 fold's left half ends past its mirror. Both: the 16x2x16
        // checks hold, and the 64x2x64 fold still ends frames up to 6.8 mm inside the rod (the two would need one loop,
        // the obstacle planes inside the passes).
        // The passes of afterImplicitSolve left each pair measured since its masses last moved, apart from those of
        // their last pass's responses and those still waiting (m_moved); since then only the obstacle contact has
        // moved masses. So the first pass here, too, measures only the pairs of those masses, and finds what
        // measuring every pair would, bit for bit: a pair none of whose masses moved is found as it was, not
        // touching, and has not crossed (its substep began where it is). One full measure a frame instead of two.
        const StageScope stage(m_observer, Stage::SelfContactSolve);
        const bool settled = m_settledAfterSolve;
        m_settledAfterSolve = false;
        if (settled)
        {
            for (const Index i : m_vertices)
            {
                if (p.position[i] != m_substepStart[i])
                {
                    m_moved.add(i);
                }
            }
        }
        respondUntilSettled(p, h, time, settled);
        m_substepStart = p.position;
        return;
    }
    if (m_substepStart.size() != p.size())
    {
        m_substepStart = p.position; // no frame has begun (a caller taking substeps alone): nothing to sweep from
    }
    if (outgrewPairs(p.position))
    {
        const StageScope stage(m_observer, Stage::SelfContactPairs);
        listPairs(p.position);
    }
    const StageScope stage(m_observer, Stage::SelfContactSolve);
    // The explicit integrators' substeps are short: one pass of responses a substep, and the next substep's pass
    // takes what a mass pushed by several pairs was left with.
    measureTriangleBoxes(p.position, true);
    const std::size_t touches = detectAndRespond(p, h, time, nullptr).touches;
    m_report.lastSubstep = touches;
    m_report.lastFrame += touches;
    m_report.total += touches;
    m_substepStart = p.position;
}

void SelfContact::afterImplicitSolve(MassSpringSystem& system, StepContext& context, Real h, Real time)
{
    Particles& p = system.particles;
    // Which constrained masses the solve had to pull back towards their triangle: they were leaving.
    std::fill(m_leaving.begin(), m_leaving.end(), std::uint8_t(0));
    for (const auto& [mass, k] : m_constraints)
    {
        const VelocityConstraint& c = context.constraints[k];
        m_leaving[mass] = c.reaction.dot(c.normal) < 0 ? 1 : 0;
    }
    m_constraints.clear();
    {
        // One solve took the whole frame: list the pairs again over its motion, so that every pair that came within
        // the radius at some moment of the step, its masses moving in straight lines, is listed for the swept test.
        // Swept boxes: spheres of each mass's move about it listed 27 to 34 million pairs a frame at 128x2x128.
        const StageScope stage(m_observer, Stage::SelfContactPairs);
        for (const Index i : m_vertices)
        {
            m_skin[i] = Real(0.25) * m_settings.radius;
        }
        m_broadphase.findSweptPairs(m_substepStart, p.position, m_skin, m_settings.radius, m_vertices, m_excluded,
                                    m_pairs);
        pairsListed(p.position);
    }
    const StageScope stage(m_observer, Stage::SelfContactSolve);
    // No substep follows the solve to take what a mass pushed by several pairs was left with, so the passes go on
    // until none moves a mass, at most selfResponsePasses. Under backward Euler the 16x2x16 fold over the rod ends
    // its frames with its halves a radius apart from 8 passes on; the wrap's flaps, pressed together between the grabs
    // and the box, keep the radius with 128 (some frames take 100).
    const std::size_t firstPass = respondUntilSettled(p, h, time, false);
    m_report.lastSubstep = firstPass;
    m_report.lastFrame += firstPass;
    m_report.total += firstPass;
    m_substepStart = p.position;
    m_settledAfterSolve = true;
}

std::size_t SelfContact::respondUntilSettled(Particles& p, Real h, Real time, bool firstOnlyMoved)
{
    // With one solve a frame the pairs are listed over the whole step's motion (1 to 5 million on the 128x2x128 fold)
    // and the passes often go on to the last: measuring every pair at every pass would be half the 64x2x64 fold's run.
    // A pass after the first measures only the pairs of the masses a response of the pass before moved by more than the
    // settling bound (pushed or slid by friction). Most responses are pairs that already rest a radius apart and are
    // put back to it by a hair (78% of them on the 128x2x128 fold's first second): their masses wait, and only when a
    // pass moves nothing does one more pass measure the pairs of every mass changed since its pairs were last measured.
    // The passes end when that pass moves nothing either, so they end as measuring every changed mass's pairs at every
    // pass would: with no response beyond the bound. On that fold the passes measure 145 million pairs in 1,882 passes.
    std::size_t firstPass = 0;
    const std::vector<Index>* measured = nullptr;
    if (firstOnlyMoved)
    {
        m_measuring = m_moved.masses;
        measured = &m_measuring;
    }
    bool everyChanged = true; // the pass measures the pairs of every mass changed since its pairs were last measured
    for (int pass = 0; pass < selfResponsePasses; ++pass)
    {
        // Between passes only the responses move masses, and m_moved holds them: only their triangles' boxes change.
        if (pass == 0)
        {
            measureTriangleBoxes(p.position, true);
        }
        else
        {
            for (const Index i : m_moved.masses)
            {
                for (std::size_t k = m_trianglesOfStart[i]; k < m_trianglesOfStart[i + 1]; ++k)
                {
                    measureTriangle(p.position, m_trianglesOf[k], true);
                }
            }
        }
        const Passed passed = detectAndRespond(p, h, time, measured);
        firstPass = pass == 0 ? passed.touches : firstPass;
        measured = &m_measuring;
        if (passed.moved > 0)
        {
            m_measuring = m_pushed.masses;
            everyChanged = false;
            continue;
        }
        if (everyChanged)
        {
            break;
        }
        m_measuring.clear();
        m_waiting.moveInto(m_measuring);
        if (m_measuring.empty())
        {
            break;
        }
        everyChanged = true;
    }
    // The masses still waiting have changed since their pairs were last measured, as the last pass's have: the next
    // passes (afterSubstep's) begin with all their pairs.
    m_measuring.clear();
    m_waiting.moveInto(m_measuring);
    for (const Index i : m_measuring)
    {
        m_moved.add(i);
    }
    return firstPass;
}

SelfContact::Passed SelfContact::detectAndRespond(Particles& p, Real h, Real time, const std::vector<Index>* measured)
{
    const std::vector<Vec3>& x = p.position;
    // A pass of some masses' pairs marks them in a bitmap over the list, from each mass's own pairs and its
    // triangles' (indexPairs), and each range of pairs measures its marked ones in pair order: a scan of every pair for
    // whether a mass of it moved would take as long as the measures, the passes being up to 128 a frame over lists of
    // millions of pairs.
    if (measured)
    {
        markPairsOf(*measured);
    }
    parallelFor(m_pairs.size(), selfPairChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    std::vector<Touch>& touches = m_touches[begin / selfPairChunkSize];
                    touches.clear();
                    if (!measured)
                    {
                        for (std::size_t k = begin; k < end; ++k)
                        {
                            detectPair(x, k, touches);
                        }
                        return;
                    }
                    // A range starts on a word of the bitmap (selfPairChunkSize is a multiple of 64) and clears the
                    // words it reads for the next pass.
                    for (std::size_t word = begin / 64; word * 64 < end; ++word)
                    {
                        std::uint64_t bits = m_pairMarks[word];
                        m_pairMarks[word] = 0;
                        while (bits != 0)
                        {
                            detectPair(x, word * 64 + std::size_t(__builtin_ctzll(bits)), touches);
                            bits &= bits - 1;
                        }
                    }
                });
    // The measured masses no longer wait (their flags lowered, their entries left for clear()).
    if (!measured)
    {
        m_waiting.clear();
    }
    else
    {
        for (const Index i : *measured)
        {
            m_waiting.has[i] = 0;
        }
    }
    m_moved.clear();
    m_pushed.clear();
    // The responses in pair order, one after the other: touching pairs share masses.
    std::size_t count = 0;
    std::size_t movedCount = 0;
    const std::size_t ranges = chunkCount(m_pairs.size(), selfPairChunkSize);
    for (std::size_t range = 0; range < ranges; ++range)
    {
        for (const Touch& touch : m_touches[range])
        {
            const SelfContactPair& pair = m_pairs[touch.pair];
            if (m_report.firstTime < 0)
            {
                m_report.firstTime = time;
                m_report.firstVertex = pair.vertex;
                m_report.firstPosition = p.position[m_report.firstVertex];
            }
            const Responded responded = respond(p, touch, h);
            movedCount += responded.moved ? 1 : 0;
            // Every mass a response may change, whether or not it moves them beyond rounding.
            const Triangle& t = m_triangles[pair.triangle];
            for (const Index i : {pair.vertex, t[0], t[1], t[2]})
            {
                m_moved.add(i);
                (responded.displaced ? m_pushed : m_waiting).add(i);
            }
        }
        count += m_touches[range].size();
    }
    return {count, movedCount};
}

void SelfContact::listTrianglesOfMasses(std::size_t n)
{
    // Counted, summed into starts, then filled: each mass's triangles in increasing order.
    m_trianglesOfStart.assign(n + 1, 0);
    for (const Triangle& t : m_triangles)
    {
        for (const Index i : t)
        {
            ++m_trianglesOfStart[i + 1];
        }
    }
    for (std::size_t i = 0; i < n; ++i)
    {
        m_trianglesOfStart[i + 1] += m_trianglesOfStart[i];
    }
    m_trianglesOf.resize(m_trianglesOfStart[n]);
    std::vector<std::size_t> filled(m_trianglesOfStart.begin(), m_trianglesOfStart.end() - 1);
    for (std::size_t k = 0; k < m_triangles.size(); ++k)
    {
        for (const Index i : m_triangles[k])
        {
            m_trianglesOf[filled[i]++] = Index(k);
        }
    }
}

void SelfContact::indexPairs()
{
    // The list comes by vertex, in increasing order: each mass's own pairs are one run. Each triangle's pairs are
    // counted, summed into starts, then filled in increasing order.
    m_pairsOfVertexStart.assign(m_moved.has.size() + 1, 0);
    m_pairsOfTriangleStart.assign(m_triangles.size() + 1, 0);
    for (const SelfContactPair& pair : m_pairs)
    {
        ++m_pairsOfVertexStart[pair.vertex + 1];
        ++m_pairsOfTriangleStart[pair.triangle + 1];
    }
    for (std::size_t i = 0; i + 1 < m_pairsOfVertexStart.size(); ++i)
    {
        m_pairsOfVertexStart[i + 1] += m_pairsOfVertexStart[i];
    }
    for (std::size_t t = 0; t + 1 < m_pairsOfTriangleStart.size(); ++t)
    {
        m_pairsOfTriangleStart[t + 1] += m_pairsOfTriangleStart[t];
    }
    m_pairsOfTriangle.resize(m_pairs.size());
    m_pairsFilled.assign(m_pairsOfTriangleStart.begin(), m_pairsOfTriangleStart.end() - 1);
    for (std::size_t k = 0; k < m_pairs.size(); ++k)
    {
        m_pairsOfTriangle[m_pairsFilled[m_pairs[k].triangle]++] = std::uint32_t(k);
    }
    m_pairMarks.assign((m_pairs.size() + 63) / 64, 0);
    m_pairsIndexed = true;
}

void SelfContact::markPairsOf(const std::vector<Index>& masses)
{
    if (!m_pairsIndexed)
    {
        indexPairs();
    }
    const auto mark = [&](std::size_t k) { m_pairMarks[k / 64] |= std::uint64_t(1) << (k % 64); };
    for (const Index i : masses)
    {
        for (std::size_t k = m_pairsOfVertexStart[i]; k < m_pairsOfVertexStart[i + 1]; ++k)
        {
            mark(k);
        }
        for (std::size_t j = m_trianglesOfStart[i]; j < m_trianglesOfStart[i + 1]; ++j)
        {
            const Index t = m_trianglesOf[j];
            for (std::size_t e = m_pairsOfTriangleStart[t]; e < m_pairsOfTriangleStart[t + 1]; ++e)
            {
                mark(m_pairsOfTriangle[e]);
            }
        }
    }
}
} // namespace masse
