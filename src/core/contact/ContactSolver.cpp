#include "core/contact/ContactSolver.h"

#include "core/Format.h"
#include "core/InputError.h"
#include "core/NamedEnum.h"
#include "core/contact/ContactProjection.h"
#include "core/parallel/TaskPool.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace masse
{
ContactResponse parseContactResponse(std::string_view name)
{
    return parseEnum(contactResponseTable, name, "response", "response");
}

std::string_view contactResponseName(ContactResponse response)
{
    return enumName(contactResponseTable, response);
}

std::vector<std::string> contactResponseNames()
{
    return namesOf(contactResponseTable);
}

void validate(const ContactSettings& settings)
{
    if (!(settings.radius > 0) || !std::isfinite(settings.radius))
    {
        throw InputError("radius", "must be a positive number of metres (got " + formatNumber(settings.radius) + ")");
    }
    if (!(settings.friction >= 0) || !std::isfinite(settings.friction))
    {
        throw InputError("friction", "must be >= 0 (got " + formatNumber(settings.friction) + ")");
    }
    if (!(settings.stickReleaseForce >= 0) || !std::isfinite(settings.stickReleaseForce))
    {
        throw InputError("stickReleaseForce", "must be >= 0 N (got " + formatNumber(settings.stickReleaseForce) + ")");
    }
    if (!(settings.drivenReach >= 0) || !std::isfinite(settings.drivenReach))
    {
        throw InputError("drivenReach", "must be >= 0 m (got " + formatNumber(settings.drivenReach) + ")");
    }
}

ContactSolver::ContactSolver(ContactDetector& detector, const ContactSettings& settings) : m_detector(detector)
{
    setSettings(settings);
}

void ContactSolver::setSettings(const ContactSettings& settings)
{
    validate(settings);
    bool anySticky = settings.response == ContactResponse::Sticky;
    for (const ObstacleContact& own : settings.perObstacle)
    {
        anySticky = anySticky || (own.own && own.response == ContactResponse::Sticky);
    }
    if (!anySticky)
    {
        releaseAll();
    }
    m_settings = settings;
}

void ContactSolver::detect(MassSpringSystem& system, StepContext& context, Real time, Real dt, bool constrain)
{
    const StageScope stage(m_observer, Stage::ContactDetection);
    const Particles& p = system.particles;
    const std::size_t n = p.size();
    m_stuck.resize(n);
    m_constraints.resize(n);
    m_report.beginFrame(n, std::size_t(m_detector.obstacleCount()));
    m_reach.resize(n);
    m_frameStart.resize(n);
    m_frameTime = time;
    m_frameDt = dt;
    m_elapsed = 0;

    // How far each mass can get this frame: its current speed plus twice the distance its current acceleration
    // would carry it, plus a radius of slack. A mass that outruns this is caught by the sweep at the end of the frame.
    // A stuck mass moves with its anchor, which the detector's obstacle travel covers: its reach is the slack alone.
    // Its force is no measure of its motion (a forming pressure of 80 kPa on a 2 mm sheet's mass is some 1e5 m/s^2,
    // met by the mould), and a search that wide would walk the whole mould for every mass on it. Nor is a pinned
    // mass's: it moves at its own velocity, and its force holds the clamp's reaction. Nor, in an implicit frame, is
    // a free mass's: the solve meets the force with the springs' stiffness, and the motion limit splits a frame whose
    // motion it foresees beyond drivenReach; the force's share of the reach is capped there. On the vacuum cup at
    // 64x2x64 the uncapped force term puts some 47 mould triangles within the search distance of each query, the
    // capped one 4, with the same planes kept (the nearest and those the mass lies over) and the same bits.
    // The frame's other per-mass resets go in the same pass over the masses.
    const Real gravity = system.forces.gravity.norm();
    const Real drivenCap = m_settings.drivenReach > 0 ? m_settings.drivenReach : std::numeric_limits<Real>::infinity();
    parallelFor(n, massChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    for (std::size_t i = begin; i < end; ++i)
                    {
                        const Real acceleration = gravity + p.force[i].norm() / p.mass[i];
                        const Real driven = p.pinned[i] ? Real(0) : acceleration * dt * dt;
                        m_reach[i] = m_stuck.stuck[i]
                                         ? m_settings.radius
                                         : p.velocity[i].norm() * dt + std::min(driven, drivenCap) + m_settings.radius;
                        m_frameStart[i] = p.position[i];
                        m_report.clearMass(i);
                    }
                });
    m_detector.setTime(time);
    m_detector.findContacts(p.position, m_reach, m_settings.radius, dt, m_planes.lists());
    m_planes.index();
    m_startOverlap.update(p, m_planes, m_settings.radius);
    // A stuck mass moves with the point of its obstacle it is stuck to, as that point moves during this frame.
    m_stuck.followSurfaces(m_detector, dt);
    m_detector.setTime(time + dt);

    context.constraints.clear();
    m_constraints.beginFrame(p, m_planes, m_stuck, m_settings, dt, constrain, context);
}

void ContactSolver::project(MassSpringSystem& system, const StepContext& context, Real h)
{
    const StageScope stage(m_observer, Stage::ContactProjection);
    Particles& p = system.particles;
    m_elapsed += h;

    // Stuck masses hold their anchors (moving with a kinematic surface) until the pull off the surface exceeds the
    // release force. The pull is the total force of this substep's evaluation, along the surface normal.
    m_stuck.hold(p, h, m_settings.stickReleaseForce, m_report, now());
    m_constraints.afterSubstep(p, context, m_stuck, h, now(), m_report);

    // The masses with planes, over ranges of their list: a chunk touches only its own masses. First touches of an
    // obstacle are collected per chunk and recorded in chunk order, the order a serial loop would find them.
    // The per-chunk lists keep their capacity from substep to substep: no allocation once the sheet has settled.
    const std::size_t masses = m_planes.massCount();
    m_chunkFirstTouches.resize(chunkCount(masses, ContactPlanes::runLength));
    for (std::size_t chunk = 0; chunk < m_chunkFirstTouches.size(); ++chunk)
    {
        m_chunkFirstTouches[chunk].clear();
    }
    m_chunkMadeStuck.assign(m_chunkFirstTouches.size(), 0);
    const Real moveStep = context.moveStep > 0 ? context.moveStep : h;
    const ContactProjection projection{p,        m_planes,  m_settings, m_constraints, m_stuck, m_startOverlap,
                                       m_report, m_elapsed, moveStep};
    parallelFor(masses, ContactPlanes::runLength,
                [&](std::size_t begin, std::size_t end)
                {
                    const std::size_t chunk = begin / ContactPlanes::runLength;
                    bool stuck = false;
                    projection.run(begin, end, m_chunkFirstTouches[chunk], stuck);
                    m_chunkMadeStuck[chunk] = stuck ? 1 : 0;
                });
    for (std::size_t chunk = 0; chunk < m_chunkFirstTouches.size(); ++chunk)
    {
        m_stuck.any = m_stuck.any || m_chunkMadeStuck[chunk] != 0;
        m_report.recordFirstTouches(m_chunkFirstTouches[chunk], now());
    }
}

void ContactSolver::keepInFront(Index i, Vec3& x, Vec3& v) const
{
    // The masses with planes are listed in increasing order.
    std::size_t first = 0;
    std::size_t last = m_planes.massCount();
    while (first < last)
    {
        const std::size_t middle = first + (last - first) / 2;
        if (m_planes.mass(middle) < i)
        {
            first = middle + 1;
        }
        else
        {
            last = middle;
        }
    }
    if (first == m_planes.massCount() || m_planes.mass(first) != i)
    {
        return;
    }
    for (std::size_t k = m_planes.firstPlane(first); k < m_planes.endPlane(first); ++k)
    {
        const ContactPlane plane = m_planes[k];
        Real separation = plane.separation(x, m_settings.radius) - plane.normal.dot(plane.velocity) * m_elapsed;
        if (m_startOverlap.any)
        {
            separation += m_startOverlap.depth[i];
        }
        // Only a centre put behind the surface: a shallower overlap is the next frame's projection's, which
        // finds the same surface in front of the centre and gives the contact its friction or its stick.
        if (separation < -m_settings.radius)
        {
            x -= separation * plane.normal;
            const Real approach = (v - plane.velocity).dot(plane.normal);
            if (approach < 0)
            {
                v -= approach * plane.normal;
            }
        }
    }
}

void ContactSolver::run(StepStage stage, const StageCall& call)
{
    switch (stage)
    {
    case StepStage::ContactDetection:
        detect(call.system, call.context, call.time, call.plan.dt, call.plan.constrain);
        break;
    case StepStage::ContactProjection:
        project(call.system, call.context, call.plan.substep);
        break;
    case StepStage::ContactReport:
        sweepAndReport(call.system, call.context, call.time);
        break;
    default:
        return;
    }
    // After every stage: the report's per-mass vector may have been resized by it.
    call.context.touchingObstacle = m_report.touchingObstacle();
}

void ContactSolver::sweepAndReport(MassSpringSystem& system, StepContext& context, Real time)
{
    const StageScope stage(m_observer, Stage::ContactSweep);
    context.constraints.clear();
    Particles& p = system.particles;
    const Real radius = m_settings.radius;
    m_elapsed = time - m_frameTime;

    // Masses that moved beyond their reach had no plane for what they may have crossed: sweep their path. Stuck
    // masses sit at their anchors, which are outside by construction. Which masses moved that far is found over
    // chunks on all threads (a pass over every mass); the few sweeps then run in mass order.
    const std::size_t chunks = chunkCount(p.size(), massChunkSize);
    m_chunkOutran.reserveChunks(chunks);
    parallelFor(p.size(), massChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    std::vector<Index>& outran = m_chunkOutran[begin / massChunkSize];
                    outran.clear();
                    for (std::size_t i = begin; i < end; ++i)
                    {
                        if (!p.pinned[i] && !m_stuck.stuck[i] &&
                            !((p.position[i] - m_frameStart[i]).norm() <= m_reach[i] - radius))
                        {
                            outran.push_back(Index(i));
                        }
                    }
                });
    for (std::size_t chunk = 0; chunk < chunks; ++chunk)
    {
        for (const Index mass : m_chunkOutran[chunk])
        {
            sweep(p, mass);
        }
    }
    m_report.endFrame(m_frameDt);
}

void ContactSolver::sweep(Particles& p, std::size_t i)
{
    const Vec3 travel = p.position[i] - m_frameStart[i];
    const std::optional<SweepHit> hit = m_detector.sweep(m_frameStart[i], p.position[i], m_settings.radius);
    if (!hit)
    {
        return;
    }
    // Stop just before the surface and drop the velocity into it.
    const Real fraction = std::max(Real(0), hit->fraction - Real(1e-9));
    p.position[i] = m_frameStart[i] + fraction * travel;
    const Real normalSpeed = p.velocity[i].dot(hit->normal);
    if (normalSpeed < 0)
    {
        const Vec3 before = p.velocity[i];
        p.velocity[i] -= normalSpeed * hit->normal;
        m_report.addImpulse(i, p.mass[i] * (p.velocity[i] - before));
    }
    m_report.touch(Index(i), hit->obstacle, hit->face, now());
}

Real ContactSolver::maxPenetration(const MassSpringSystem& system)
{
    Real deepest = 0;
    const Real radius = m_settings.radius;
    for (const Vec3& x : system.particles.position)
    {
        const SurfaceDistance nearest = m_detector.nearestSurface(x, radius);
        if (nearest.obstacle >= 0)
        {
            deepest = std::max(deepest, radius - nearest.distance);
        }
    }
    return deepest;
}
} // namespace masse
