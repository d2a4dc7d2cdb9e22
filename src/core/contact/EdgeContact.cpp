#include "core/contact/EdgeContact.h"

#include "core/contact/ClosestPointOnTriangle.h"
#include "core/contact/ClosestPointsOfSegments.h"
#include "core/parallel/TaskPool.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace masse
{
namespace
{
/// Pairs per range of the substep's detection: enough work to pay for waking a thread.
constexpr std::size_t edgePairChunkSize = 1024;
/// Surface masses per range of the check that they are still within their reach.
constexpr std::size_t reachChunkSize = 8192;
} // namespace

EdgeContact::EdgeContact(const Lattice& lattice, EdgeContactDetector& detector, const ContactSettings& settings)
    : m_detector(detector), m_settings(settings), m_surface(sheetSurface(lattice, SheetFaces::Volume))
{
    validate(settings);
    const std::size_t n = lattice.massCount();
    m_reach.assign(n, 0);
    m_listedAt.assign(n, Vec3::Zero());
    m_frameStart.assign(n, Vec3::Zero());
    m_massTouches.assign(n, 0);
    m_detector.setSurface(m_surface);
}

void EdgeContact::computeReach(const Particles& p, const Vec3& gravity, Real dt)
{
    // As the obstacle contact reckons a mass's reach (its speed plus twice what its acceleration would add over the
    // frame, that share capped at drivenReach in implicit frames: ContactSolver.cpp says why), with a quarter radius
    // of slack so that a mass at rest does not make every substep list the pairs again. Uncapped, a forming
    // pressure's 1e5 m/s^2 on a sheet's masses lists every sheet edge against every mould edge.
    const Real g = gravity.norm();
    const Real slack = Real(0.25) * m_settings.radius;
    const Real drivenCap = m_settings.drivenReach > 0 ? m_settings.drivenReach : std::numeric_limits<Real>::infinity();
    parallelFor(m_surface.vertices.size(), reachChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    for (std::size_t k = begin; k < end; ++k)
                    {
                        const Index i = m_surface.vertices[k];
                        const Real acceleration = g + p.force[i].norm() * p.inverseMass[i];
                        m_reach[i] = p.velocity[i].norm() * dt + std::min(acceleration * dt * dt, drivenCap) + slack;
                    }
                });
}

void EdgeContact::listPairs(const std::vector<Vec3>& x, Real time, Real dt)
{
    m_detector.findCandidates(x, m_reach, m_settings.radius, time, dt, m_candidates);
    m_listTime = time;
    for (const Index i : m_surface.vertices)
    {
        m_listedAt[i] = x[i];
    }
    // Each range's list can hold every pair of its range, so the substeps never allocate.
    const std::size_t pairs = m_candidates.edgePairs.size() + m_candidates.cornerPairs.size();
    const std::size_t ranges = chunkCount(pairs, edgePairChunkSize);
    m_touches.reserveChunks(ranges);
    for (std::size_t range = 0; range < m_touches.size(); ++range)
    {
        m_touches[range].reserve(edgePairChunkSize);
    }
    m_report.edgePairs = m_candidates.edgePairs.size();
    m_report.cornerPairs = m_candidates.cornerPairs.size();
    ++m_report.lists;
}

bool EdgeContact::outgrewPairs(const std::vector<Vec3>& x)
{
    m_chunkOutgrew.assign(chunkCount(m_surface.vertices.size(), reachChunkSize), 0);
    parallelFor(m_surface.vertices.size(), reachChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    for (std::size_t k = begin; k < end; ++k)
                    {
                        const Index i = m_surface.vertices[k];
                        if ((x[i] - m_listedAt[i]).squaredNorm() >= m_reach[i] * m_reach[i])
                        {
                            m_chunkOutgrew[begin / reachChunkSize] = 1;
                            return;
                        }
                    }
                });
    return std::any_of(m_chunkOutgrew.begin(), m_chunkOutgrew.end(), [](std::uint8_t b) { return b != 0; });
}

void EdgeContact::beginFrame(MassSpringSystem& system, StepContext& /*context*/, Real time, Real dt)
{
    const StageScope stage(m_observer, Stage::EdgeContactPairs);
    m_frameEnd = time + dt;
    m_frameStartTime = time;
    for (const Index i : m_surface.vertices)
    {
        m_frameStart[i] = system.particles.position[i];
    }
    computeReach(system.particles, system.forces.gravity, dt);
    listPairs(system.particles.position, time, dt);
    m_report.lastFrame = 0;
    m_report.lastSubstep = 0;
    for (const Index i : m_surface.vertices)
    {
        m_massTouches[i] = 0;
    }
}

bool EdgeContact::measure(const std::vector<Vec3>& x, std::size_t k, Real elapsed, Contact& out) const
{
    const Real radius = m_settings.radius;
    Vec3 offset;  // from the obstacle's point to the sheet's
    bool inside;  // the sheet's point is behind every face at the feature
    Vec3 outward; // the mean of those faces' normals, for a sheet point on the feature itself
    Vec3 obstaclePoint;
    bool insideAtFrameStart; // the same point of the sheet (the same weights of its masses) was inside then
    Vec3 startOffset;        // from the obstacle's point to the sheet's at the frame's start
    if (k < m_candidates.edgePairs.size())
    {
        const SheetEdgePair& pair = m_candidates.edgePairs[k];
        const Edge& e = m_surface.edges[pair.sheetEdge];
        const ObstacleEdge& o = m_candidates.edges[pair.obstacleEdge];
        const Vec3 a = o.start + elapsed * o.startVelocity;
        const Vec3 b = o.end + elapsed * o.endVelocity;
        const SegmentParameters at = closestPointsOfSegments(x[e[0]], x[e[1]], a, b);
        // An end of the sheet edge is a mass (the mass's own contact); an end of the obstacle edge is a corner (the
        // corner's pairs).
        if (!(at.s > 0 && at.s < 1 && at.t > 0 && at.t < 1))
        {
            return false;
        }
        out.point = x[e[0]] + at.s * (x[e[1]] - x[e[0]]);
        obstaclePoint = a + at.t * (b - a);
        offset = out.point - obstaclePoint;
        inside = offset.dot(o.normals[0]) <= 0 && offset.dot(o.normals[1]) <= 0;
        const Vec3 obstacleVelocity = o.startVelocity + at.t * (o.endVelocity - o.startVelocity);
        startOffset = m_frameStart[e[0]] + at.s * (m_frameStart[e[1]] - m_frameStart[e[0]]) -
                      (o.start + at.t * (o.end - o.start)) - (m_frameStartTime - m_listTime) * obstacleVelocity;
        insideAtFrameStart = startOffset.dot(o.normals[0]) <= 0 && startOffset.dot(o.normals[1]) <= 0;
        outward = o.normals[0] + o.normals[1];
        out.masses[0] = e[0];
        out.masses[1] = e[1];
        out.weights[0] = 1 - at.s;
        out.weights[1] = at.s;
        out.count = 2;
        out.obstacleVelocity = obstacleVelocity;
        out.obstacle = o.obstacle;
    }
    else
    {
        const SheetTrianglePair& pair = m_candidates.cornerPairs[k - m_candidates.edgePairs.size()];
        const Triangle& t = m_surface.triangles[pair.triangle];
        const ObstacleCorner& o = m_candidates.corners[pair.corner];
        obstaclePoint = o.point + elapsed * o.velocity;
        const Vec3 w = closestPointWeights(obstaclePoint, x[t[0]], x[t[1]], x[t[2]]);
        if (w[0] == 1 || w[1] == 1 || w[2] == 1)
        {
            return false; // a mass: its own contact
        }
        out.point = w[0] * x[t[0]] + w[1] * x[t[1]] + w[2] * x[t[2]];
        offset = out.point - obstaclePoint;
        startOffset = w[0] * m_frameStart[t[0]] + w[1] * m_frameStart[t[1]] + w[2] * m_frameStart[t[2]] -
                      (o.point + (m_frameStartTime - m_listTime) * o.velocity);
        inside = true;
        insideAtFrameStart = true;
        outward = Vec3::Zero();
        for (std::uint32_t n = o.firstNormal; n < o.firstNormal + o.normalCount; ++n)
        {
            const Vec3& normal = m_candidates.cornerNormals[n];
            inside = inside && offset.dot(normal) <= 0;
            insideAtFrameStart = insideAtFrameStart && startOffset.dot(normal) <= 0;
            outward += normal;
        }
        for (int j = 0; j < 3; ++j)
        {
            out.masses[j] = t[std::size_t(j)];
            out.weights[j] = w[j];
        }
        out.count = 3;
        out.obstacleVelocity = o.velocity;
        out.obstacle = o.obstacle;
    }
    const Real distanceSquared = offset.squaredNorm();
    // Further than a radius, a point counts only if it has gone through the feature in this frame: one implicit solve
    // moves the sheet a whole frame at once and can carry a sheet edge clean over a ridge, which it then straddles
    // deeper than a radius (a knife's apex between the two masses of a spring). It must have been outside the
    // feature's faces at the frame's start and be no further from the feature than it has moved since: a point
    // already behind them did not come through now, and one further in came through another feature (a sheet edge
    // under a knife's ridge is behind the faces of the ridge's end corner too, a ridge's length away).
    const Real moved = (offset - startOffset).norm();
    if (!(distanceSquared < radius * radius) &&
        !(inside && !insideAtFrameStart && distanceSquared < (radius + moved) * (radius + moved)))
    {
        return false;
    }
    const Real distance = std::sqrt(distanceSquared);
    if (distance > Real(1e-9) * radius)
    {
        // Inside the obstacle (it got through within one substep): back out through the feature, the way it came.
        out.normal = (inside ? -offset : offset) / distance;
        out.depth = inside ? radius + distance : radius - distance;
    }
    else
    {
        const Real length = outward.norm();
        if (!(length > 0))
        {
            return false;
        }
        out.normal = outward / length;
        out.depth = radius;
    }
    return true;
}

void EdgeContact::respond(Particles& p, const Contact& contact, Real h) const
{
    const Real* w = contact.weights;
    const Index* m = contact.masses;
    // The generalised inverse mass of the sheet's point: an impulse J there, shared as w_k J over its masses, changes
    // the point's velocity by this times J. The obstacle does not move.
    Real inverseMass = 0;
    for (int k = 0; k < contact.count; ++k)
    {
        inverseMass += w[k] * w[k] * p.inverseMass[m[k]];
    }
    if (!(inverseMass > 0))
    {
        return; // all pinned
    }
    const auto apply = [&](std::vector<Vec3>& field, const Vec3& change)
    {
        for (int k = 0; k < contact.count; ++k)
        {
            field[m[k]] += (w[k] * p.inverseMass[m[k]]) * change;
        }
    };
    // The point out to the radius: the weighted masses move so that their weighted sum moves by exactly the depth.
    apply(p.position, (contact.depth / inverseMass) * contact.normal);

    Vec3 velocity = Vec3::Zero();
    for (int k = 0; k < contact.count; ++k)
    {
        velocity += w[k] * p.velocity[m[k]];
    }
    const Vec3 relative = velocity - contact.obstacleVelocity;
    const Real normalSpeed = relative.dot(contact.normal);
    if (normalSpeed >= 0)
    {
        return; // already leaving
    }
    // Inelastic: the impulse that stops the approach. Friction takes at most mu times it (all of the slip if sticky),
    // and never more than stops the slip, so both only take kinetic energy away.
    const Real normalImpulse = -normalSpeed / inverseMass;
    const Vec3 tangential = relative - normalSpeed * contact.normal;
    const Real slip = tangential.norm();
    Vec3 frictionImpulse = Vec3::Zero();
    if (slip > 0)
    {
        Real magnitude = slip / inverseMass;
        switch (m_settings.responseOf(contact.obstacle))
        {
        case ContactResponse::Sticky:
            break;
        case ContactResponse::Friction:
            magnitude = std::min(magnitude, m_settings.frictionOf(contact.obstacle) * normalImpulse);
            break;
        case ContactResponse::Frictionless:
            magnitude = 0;
            break;
        }
        frictionImpulse = (-magnitude / slip) * tangential;
    }
    apply(p.velocity, normalImpulse * contact.normal + frictionImpulse);
    // The integrator moved the masses with their velocities from before the impulse: move them by the friction's
    // change too, as the obstacle contact does, so a sheet held by static friction on a ridge does not creep.
    apply(p.position, h * frictionImpulse);
}

void EdgeContact::afterSubstep(MassSpringSystem& system, StepContext& /*context*/, Real h, Real time)
{
    Particles& p = system.particles;
    // A mass beyond its reach lists the pairs again, unless the sheet was clear of every feature by more than a
    // radius beyond the reach of its masses: a mass would then have outrun its reach (twice what its speed and
    // acceleration take it, and a quarter radius) by a radius more within the frame. The pass over the masses, every
    // substep, cost up to a tenth of a 256x2x256 sheet's step in free fall.
    if (m_candidates.clearance < m_settings.radius && outgrewPairs(p.position))
    {
        const StageScope stage(m_observer, Stage::EdgeContactPairs);
        computeReach(p, system.forces.gravity, std::max(m_frameEnd - time, h));
        listPairs(p.position, time, std::max(m_frameEnd - time, h));
    }
    const std::size_t pairs = m_candidates.edgePairs.size() + m_candidates.cornerPairs.size();
    if (pairs == 0)
    {
        m_report.lastSubstep = 0;
        return;
    }
    const StageScope stage(m_observer, Stage::EdgeContactSolve);
    const Real elapsed = time - m_listTime;
    const std::vector<Vec3>& x = p.position;
    parallelFor(pairs, edgePairChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    std::vector<std::uint32_t>& touches = m_touches[begin / edgePairChunkSize];
                    touches.clear();
                    Contact contact;
                    for (std::size_t k = begin; k < end; ++k)
                    {
                        if (measure(x, k, elapsed, contact))
                        {
                            touches.push_back(std::uint32_t(k));
                        }
                    }
                });
    // The responses in pair order, one after the other: touching pairs share masses. Each is measured again, as an
    // earlier response in this pass may have moved its masses.
    std::size_t count = 0;
    const std::size_t ranges = chunkCount(pairs, edgePairChunkSize);
    for (std::size_t range = 0; range < ranges; ++range)
    {
        for (const std::uint32_t k : m_touches[range])
        {
            Contact contact;
            if (!measure(p.position, k, elapsed, contact))
            {
                continue;
            }
            if (m_report.firstTime < 0)
            {
                m_report.firstTime = time;
                m_report.firstObstacle = contact.obstacle;
                m_report.firstPosition = contact.point;
            }
            respond(p, contact, h);
            for (int j = 0; j < contact.count; ++j)
            {
                ++m_massTouches[contact.masses[j]];
            }
            ++count;
        }
    }
    m_report.lastSubstep = count;
    m_report.lastFrame += count;
    m_report.total += count;
}
} // namespace masse
