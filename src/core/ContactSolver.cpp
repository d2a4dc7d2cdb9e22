#include "ContactSolver.h"

#include "Format.h"
#include "InputError.h"
#include "NamedEnum.h"
#include "TaskPool.h"

#include <algorithm>
#include <cmath>
#include <string>

namespace masse
{
namespace
{
constexpr EnumName<ContactResponse> responseNames[] = {
    {ContactResponse::Sticky, "sticky"},
    {ContactResponse::Friction, "friction"},
    {ContactResponse::Frictionless, "frictionless"},
};
} // namespace

ContactResponse parseContactResponse(std::string_view name)
{
    return parseEnum(responseNames, name, "contact.response", "response");
}

std::string_view contactResponseName(ContactResponse response)
{
    return enumName(responseNames, response);
}

void validate(const ContactSettings& settings)
{
    if (!(settings.radius > 0) || !std::isfinite(settings.radius))
    {
        throw InputError("contact.radius: must be a positive number of metres (got " + formatNumber(settings.radius) +
                         ")");
    }
    if (!(settings.friction >= 0) || !std::isfinite(settings.friction))
    {
        throw InputError("contact.friction: must be >= 0 (got " + formatNumber(settings.friction) + ")");
    }
    if (!(settings.stickReleaseForce >= 0) || !std::isfinite(settings.stickReleaseForce))
    {
        throw InputError("contact.release_force: must be >= 0 N (got " + formatNumber(settings.stickReleaseForce) +
                         ")");
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

void ContactSolver::releaseAll()
{
    std::fill(m_stuck.begin(), m_stuck.end(), std::uint8_t(0));
}

bool ContactSolver::everTouched(int obstacle) const
{
    return obstacle >= 0 && std::size_t(obstacle) < m_obstacleTouched.size() &&
           m_obstacleTouched[std::size_t(obstacle)];
}

void ContactSolver::resizeFor(std::size_t masses)
{
    if (m_stuck.size() == masses)
    {
        return;
    }
    m_stuck.assign(masses, 0);
    m_anchor.assign(masses, Vec3::Zero());
    m_stuckNormal.assign(masses, Vec3::UnitY());
    m_stuckVelocity.assign(masses, Vec3::Zero());
    m_stuckObstacle.assign(masses, -1);
    m_stuckFace.assign(masses, -1);
    m_touchObstacle.assign(masses, -1);
    m_touchFace.assign(masses, -1);
    m_contactForce.assign(masses, Vec3::Zero());
    m_impulse.assign(masses, Vec3::Zero());
    m_resting.assign(masses, 0);
    m_restingNormal.assign(masses, Vec3::UnitY());
    m_restingVelocity.assign(masses, Vec3::Zero());
    m_restingDamping.assign(masses, 0);
    m_restingObstacle.assign(masses, -1);
    m_restingFace.assign(masses, -1);
    m_restingConstraint.assign(masses, 0);
    m_restingPlane.assign(masses, 0);
    m_lastReaction.assign(masses, Vec3::Zero());
    m_wasResting.assign(masses, 0);
    m_reach.assign(masses, 0);
}

void ContactSolver::beginFrame(MassSpringSystem& system, StepContext& context, Real time, Real dt, bool constrain)
{
    const StageScope stage(m_observer, Stage::ContactDetection);
    const Particles& p = system.particles;
    const std::size_t n = p.size();
    resizeFor(n);
    m_obstacleTouched.resize(std::size_t(m_detector.obstacleCount()), 0);
    m_frameTime = time;
    m_frameDt = dt;
    m_elapsed = 0;
    m_touchedFaces.clear();
    m_frameStart.resize(n);

    // How far each mass can get this frame: its current speed plus twice the distance its current acceleration
    // would carry it, plus a radius of slack. A mass that outruns this is caught by the sweep at the end of the frame.
    // The frame's other per-mass resets go in the same pass over the masses.
    const Real gravity = system.forces.gravity.norm();
    parallelFor(n, massChunkSize, [&](std::size_t begin, std::size_t end) {
        for (std::size_t i = begin; i < end; ++i)
        {
            const Real acceleration = gravity + p.force[i].norm() / p.mass[i];
            m_reach[i] = p.velocity[i].norm() * dt + acceleration * dt * dt + m_settings.radius;
            m_frameStart[i] = p.position[i];
            m_touchObstacle[i] = -1;
            m_touchFace[i] = -1;
            m_impulse[i] = Vec3::Zero();
        }
    });
    m_planes.clear();
    m_detector.setTime(time);
    m_detector.findContacts(p.position, m_reach, m_settings.radius, dt, m_planes);
    indexPlanesByMass(n);
    // A stuck mass moves with the point of its obstacle it is stuck to, as that point moves during this frame.
    if (m_anyStuck)
    {
        for (std::size_t i = 0; i < n; ++i)
        {
            if (m_stuck[i])
            {
                m_stuckVelocity[i] = m_detector.pointVelocity(m_stuckObstacle[i], m_anchor[i], dt);
            }
        }
    }
    m_detector.setTime(time + dt);

    // Constraints for the implicit integrator (see VelocityConstraint.h): stuck masses are held; a mass resting on
    // a surface keeps the surface's normal velocity, and its friction becomes a tangential damping. A mass rests if
    // it touches the surface and is not leaving it, and the surface pushed on it in the last solve (its reaction),
    // or, for a new contact, its forces press it in. When the solve's reaction would pull, it lets go.
    context.constraints.clear();
    m_wasResting.swap(m_resting);
    std::fill(m_resting.begin(), m_resting.end(), std::uint8_t(0));
    m_restingMasses.clear();
    if (!constrain)
    {
        return;
    }
    for (std::size_t i = 0; i < n; ++i)
    {
        if (m_stuck[i])
        {
            context.constraints.push_back({Index(i), 3, m_stuckNormal[i], m_stuckVelocity[i], 0, Vec3::Zero()});
        }
    }
    const Real touchTolerance = Real(1e-6) * m_settings.radius;
    for (std::size_t k = 0; k < m_planes.size(); ++k)
    {
        const ContactPlane& plane = m_planes[k];
        const Index i = plane.mass;
        if (m_stuck[i] || m_resting[i] || p.pinned[i])
        {
            continue;
        }
        const Real separation = plane.normal.dot(p.position[i]) - plane.offset - m_settings.radius;
        const Vec3 relative = p.velocity[i] - plane.velocity;
        // Leaving means faster than rounding: a held mass's normal speed is zero to about 1e-11 m/s either way.
        if (separation >= touchTolerance || relative.dot(plane.normal) > m_settings.slipRegularization)
        {
            continue;
        }
        const Real press = m_wasResting[i] ? m_lastReaction[i].dot(plane.normal) / dt : -p.force[i].dot(plane.normal);
        if (press <= 0)
        {
            continue;
        }
        Real damping = 0;
        if (m_settings.responseOf(plane.obstacle) == ContactResponse::Friction)
        {
            // The slip the damping is sized for: the current one, or, for a mass at rest pushed harder than
            // friction holds, the slip the excess push gives it within the frame. With the latter the first step
            // of a slide already has Coulomb's acceleration instead of creeping up from the regularisation speed.
            const Real limit = m_settings.frictionOf(plane.obstacle) * press;
            const Real push = (p.force[i] + press * plane.normal).norm();
            const Real slip =
                std::max({(relative - relative.dot(plane.normal) * plane.normal).norm(),
                          dt * std::max(Real(0), push - limit) * p.inverseMass[i], m_settings.slipRegularization});
            damping = limit / slip;
        }
        m_restingConstraint[i] = context.constraints.size();
        m_restingPlane[i] = k;
        context.constraints.push_back({i, 1, plane.normal, plane.velocity, damping, Vec3::Zero()});
        m_resting[i] = 1;
        m_restingMasses.push_back(i);
        m_restingNormal[i] = plane.normal;
        m_restingVelocity[i] = plane.velocity;
        m_restingDamping[i] = damping;
        m_restingObstacle[i] = plane.obstacle;
        m_restingFace[i] = plane.face;
    }
}

void ContactSolver::indexPlanesByMass(std::size_t masses)
{
    // The Bullet detector appends planes in mass order already; a test detector need not, so sort stably (each
    // mass's planes keep their order, which is the order they are applied in).
    const auto byMass = [](const ContactPlane& x, const ContactPlane& y) { return x.mass < y.mass; };
    if (!std::is_sorted(m_planes.begin(), m_planes.end(), byMass))
    {
        std::stable_sort(m_planes.begin(), m_planes.end(), byMass);
    }
    m_planeOffsets.assign(masses + 1, 0);
    for (const ContactPlane& plane : m_planes)
    {
        ++m_planeOffsets[std::size_t(plane.mass) + 1];
    }
    for (std::size_t i = 0; i < masses; ++i)
    {
        m_planeOffsets[i + 1] += m_planeOffsets[i];
    }
}

void ContactSolver::recordFirstContact(int obstacle)
{
    m_obstacleTouched[std::size_t(obstacle)] = 1;
    m_firstContacts.push_back({obstacle, m_frameTime + m_elapsed});
}

void ContactSolver::afterSubstep(MassSpringSystem& system, const StepContext& context, Real h)
{
    const StageScope stage(m_observer, Stage::ContactProjection);
    Particles& p = system.particles;
    m_elapsed += h;

    // Stuck masses hold their anchors (moving with a kinematic surface) until the pull off the surface exceeds the
    // release force. The pull is the total force of this substep's evaluation, along the surface normal.
    if (m_anyStuck)
    {
        for (std::size_t i = 0; i < p.size(); ++i)
        {
            if (!m_stuck[i])
            {
                continue;
            }
            const Real pull = p.force[i].dot(m_stuckNormal[i]);
            if (m_settings.stickReleaseForce > 0 && pull > m_settings.stickReleaseForce)
            {
                m_stuck[i] = 0;
                continue;
            }
            m_anchor[i] += h * m_stuckVelocity[i];
            m_impulse[i] += p.mass[i] * (m_stuckVelocity[i] - p.velocity[i]);
            p.position[i] = m_anchor[i];
            p.velocity[i] = m_stuckVelocity[i];
            touch(Index(i), m_stuckObstacle[i], m_stuckFace[i]);
        }
    }

    // Resting masses were handled inside the implicit solve: their contact impulse is the solve's reaction plus the
    // friction it applied as a damping.
    for (const Index i : m_restingMasses)
    {
        if (m_stuck[i])
        {
            continue;
        }
        m_lastReaction[i] = context.constraints[m_restingConstraint[i]].reaction;
        const Vec3 relative = p.velocity[i] - m_restingVelocity[i];
        const Vec3 slip = relative - relative.dot(m_restingNormal[i]) * m_restingNormal[i];
        m_impulse[i] += m_lastReaction[i] - h * m_restingDamping[i] * slip; // the reaction holds; friction drags
        touch(Index(i), m_restingObstacle[i], m_restingFace[i]);
    }

    // Each mass's planes, over mass ranges: a chunk touches only its own masses. First touches of an obstacle are
    // collected per chunk and recorded in chunk order, the order a serial loop would find them.
    const std::size_t masses = p.size();
    std::vector<std::vector<int>> firstTouches(chunkCount(masses, massChunkSize));
    std::vector<std::uint8_t> madeStuck(firstTouches.size(), 0);
    parallelFor(masses, massChunkSize, [&](std::size_t begin, std::size_t end) {
        const std::size_t chunk = begin / massChunkSize;
        bool stuck = false;
        for (std::size_t i = begin; i < end; ++i)
        {
            if (m_planeOffsets[i] != m_planeOffsets[i + 1])
            {
                projectMass(p, Index(i), h, firstTouches[chunk], stuck);
            }
        }
        madeStuck[chunk] = stuck ? 1 : 0;
    });
    for (std::size_t chunk = 0; chunk < firstTouches.size(); ++chunk)
    {
        m_anyStuck = m_anyStuck || madeStuck[chunk] != 0;
        for (const int obstacle : firstTouches[chunk])
        {
            if (!m_obstacleTouched[std::size_t(obstacle)])
            {
                recordFirstContact(obstacle);
            }
        }
    }
}

void ContactSolver::projectMass(Particles& p, Index i, Real h, std::vector<int>& firstTouches, bool& madeStuck)
{
    const Real radius = m_settings.radius;
    const Real touchTolerance = Real(1e-6) * radius;
    for (std::size_t k = m_planeOffsets[i]; k < m_planeOffsets[std::size_t(i) + 1]; ++k)
    {
        const ContactPlane& plane = m_planes[k];
        if (p.pinned[i] || m_stuck[i])
        {
            continue; // (a plane earlier in this loop may have just made it stuck)
        }
        const Real offset = plane.offset + plane.normal.dot(plane.velocity) * m_elapsed;
        const Real separation = plane.normal.dot(p.position[i]) - offset - radius;
        if (m_resting[i] && m_restingPlane[i] == k)
        {
            // The solve kept this resting mass moving with its surface; only a position error is left to mend
            // (say, a surface that started moving within the last frame).
            if (separation < 0)
            {
                p.position[i] -= separation * plane.normal;
            }
            continue;
        }
        if (separation >= touchTolerance)
        {
            continue;
        }
        if (separation < 0)
        {
            p.position[i] -= separation * plane.normal;
        }
        touchInChunk(i, plane.obstacle, plane.face, firstTouches);

        const Vec3 relative = p.velocity[i] - plane.velocity;
        const Real normalSpeed = relative.dot(plane.normal);
        if (normalSpeed >= 0)
        {
            continue; // already leaving the surface
        }
        const Vec3 before = p.velocity[i];
        Vec3 tangential = relative - normalSpeed * plane.normal;
        const ContactResponse response = m_settings.responseOf(plane.obstacle);
        switch (response)
        {
        case ContactResponse::Sticky:
            tangential.setZero();
            break;
        case ContactResponse::Friction:
        {
            const Real budget = m_settings.frictionOf(plane.obstacle) * (-normalSpeed);
            const Real speed = tangential.norm();
            tangential = speed <= budget ? Vec3::Zero() : Vec3(tangential * ((speed - budget) / speed));
            break;
        }
        case ContactResponse::Frictionless:
            break;
        }
        p.velocity[i] = plane.velocity + tangential;
        const Vec3 change = p.velocity[i] - before;
        m_impulse[i] += p.mass[i] * change;
        // The integrator already moved the mass with its velocity from before the contact. Move it by the
        // tangential change too, as if the impulse had come first; otherwise a mass held by static friction
        // would creep by h^2 g sin(a) every substep. (The normal part is handled by the projection.)
        p.position[i] += h * (change - change.dot(plane.normal) * plane.normal);
        if (response == ContactResponse::Sticky)
        {
            m_stuck[i] = 1;
            madeStuck = true;
            m_anchor[i] = p.position[i];
            m_stuckNormal[i] = plane.normal;
            m_stuckVelocity[i] = plane.velocity;
            m_stuckObstacle[i] = plane.obstacle;
            m_stuckFace[i] = plane.face;
        }
    }
}

void ContactSolver::endFrame(MassSpringSystem& system, StepContext& context, Real time)
{
    const StageScope stage(m_observer, Stage::ContactSweep);
    context.constraints.clear();
    Particles& p = system.particles;
    const Real radius = m_settings.radius;
    m_elapsed = time - m_frameTime;

    // Masses that moved beyond their reach had no plane for what they may have crossed: sweep their path. Stuck
    // masses sit at their anchors, which are outside by construction.
    for (std::size_t i = 0; i < p.size(); ++i)
    {
        const Vec3 travel = p.position[i] - m_frameStart[i];
        if (p.pinned[i] || m_stuck[i] || travel.norm() <= m_reach[i] - radius)
        {
            continue;
        }
        const std::optional<SweepHit> hit = m_detector.sweep(m_frameStart[i], p.position[i], radius);
        if (!hit)
        {
            continue;
        }
        // Stop just before the surface and drop the velocity into it.
        const Real fraction = std::max(Real(0), hit->fraction - Real(1e-9));
        p.position[i] = m_frameStart[i] + fraction * travel;
        const Real normalSpeed = p.velocity[i].dot(hit->normal);
        if (normalSpeed < 0)
        {
            const Vec3 before = p.velocity[i];
            p.velocity[i] -= normalSpeed * hit->normal;
            m_impulse[i] += p.mass[i] * (p.velocity[i] - before);
        }
        touch(Index(i), hit->obstacle, hit->face);
    }

    m_touchingCount = 0;
    const Real inverseDt = m_frameDt > 0 ? Real(1) / m_frameDt : Real(0);
    for (std::size_t i = 0; i < p.size(); ++i)
    {
        m_contactForce[i] = m_impulse[i] * inverseDt;
        if (m_touchObstacle[i] >= 0)
        {
            ++m_touchingCount;
            m_touchedFaces.emplace_back(m_touchObstacle[i], m_touchFace[i]);
        }
    }
    std::sort(m_touchedFaces.begin(), m_touchedFaces.end());
    m_touchedFaces.erase(std::unique(m_touchedFaces.begin(), m_touchedFaces.end()), m_touchedFaces.end());
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
