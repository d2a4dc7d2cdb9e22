#include "core/contact/ContactConstraints.h"

#include <algorithm>

namespace masse
{
void ContactConstraints::resize(std::size_t masses)
{
    if (m_resting.size() == masses)
    {
        return;
    }
    m_resting.assign(masses, 0);
    m_arriving.assign(masses, 0);
    m_arrived.assign(masses, 0);
    m_lastArrivalImpulse.assign(masses, 0);
    m_wasResting.assign(masses, 0);
    m_normal.assign(masses, Vec3::UnitY());
    m_velocity.assign(masses, Vec3::Zero());
    m_obstacle.assign(masses, -1);
    m_face.assign(masses, -1);
    m_constraint.assign(masses, 0);
    m_plane.assign(masses, 0);
    m_lastReaction.assign(masses, Vec3::Zero());
    m_arrivalImpulse.assign(masses, 0);
}

void ContactConstraints::beginFrame(const Particles& p, const ContactPlanes& planes, const StuckContacts& stuck,
                                    const ContactSettings& settings, Real dt, bool constrain, StepContext& context)
{
    m_wasResting.swap(m_resting);
    std::fill(m_resting.begin(), m_resting.end(), std::uint8_t(0));
    m_restingMasses.clear();
    for (const Index i : m_lastArrivedMasses)
    {
        m_lastArrivalImpulse[i] = 0;
    }
    m_lastArrivedMasses.clear();
    for (const Index i : m_arrivingMasses)
    {
        if (m_arrived[i])
        {
            m_lastArrivalImpulse[i] = m_arrivalImpulse[i];
            m_lastArrivedMasses.push_back(i);
        }
        m_arriving[i] = 0;
        m_arrived[i] = 0;
    }
    m_arrivingMasses.clear();
    if (!constrain)
    {
        return;
    }
    for (std::size_t i = 0; i < p.size(); ++i)
    {
        if (stuck.stuck[i])
        {
            context.constraints.push_back({Index(i), 3, stuck.normal[i], stuck.velocity[i], 0, Vec3::Zero()});
        }
    }
    const Real touchTolerance = Real(1e-6) * settings.radius;
    // How far from its surface a mass resting on it in the last frame may be found and still rest on it, as a share of
    // the contact radius (0.1 mm of 2 mm in the forming scenes).
    constexpr Real restingGapShare = Real(0.05);
    for (std::size_t k = 0; k < planes.size(); ++k)
    {
        const ContactPlane plane = planes[k];
        const Index i = plane.mass;
        if (stuck.stuck[i] || m_resting[i] || p.pinned[i])
        {
            continue;
        }
        const Real separation = plane.separation(p.position[i], settings.radius);
        const Vec3 relative = p.velocity[i] - plane.velocity;
        // A mass pressed on this surface in the last frame, or stopped at it, that slid along the tangent plane of a
        // curved surface is found a little off it (a plug's nose of 10 mm radius: up to 30 um). Taken as apart, it
        // arrives again in one of the solve's rounds, every frame: in the plug-assist cup's stroke the constraint set
        // then changes by tens of masses from round to round, and the factor drifts with it. It still rests while it
        // is that near and not moving off (a mass held to its surface's normal speed in the solve is not).
        const Real normalSpeed = relative.dot(plane.normal);
        const bool pressed = m_wasResting[i] && m_lastReaction[i].dot(m_normal[i]) > 0;
        const bool near = (pressed || m_lastArrivalImpulse[i] > 0) && m_obstacle[i] == plane.obstacle &&
                          separation < restingGapShare * settings.radius;
        const bool apart = separation >= touchTolerance && !near;
        // Leaving means faster than rounding: a held mass's normal speed is zero to about 1e-11 m/s either way.
        const bool leaving = normalSpeed > settings.slipRegularization;
        if (apart || leaving)
        {
            continue;
        }
        Real press = m_wasResting[i] ? m_lastReaction[i].dot(plane.normal) / dt : -p.force[i].dot(plane.normal);
        // A mass a surface advancing into the sheet caught in the last frame (a plug's nose) is pulled away from it
        // by its springs, so its forces do not press it in; the surface does, with the impulse that stopped it.
        // Left to arrive again every frame, each such mass is engaged in one of the solve's rounds and the factor
        // is refreshed for a constraint set that changes by hundreds of masses from round to round.
        if (press <= 0 && m_lastArrivalImpulse[i] > 0 && m_obstacle[i] == plane.obstacle &&
            plane.velocity.dot(plane.normal) > 0)
        {
            press = m_lastArrivalImpulse[i] / dt;
        }
        if (press <= 0)
        {
            continue;
        }
        Real damping = 0;
        if (settings.responseOf(plane.obstacle) == ContactResponse::Friction)
        {
            // The slip the damping is sized for: the current one, or, for a mass at rest pushed harder than
            // friction holds, the slip the excess push gives it within the frame. With the latter the first step
            // of a slide already has Coulomb's acceleration instead of creeping up from the regularisation speed.
            // The push is the force along the surface: where a surface advances into the sheet (a plug's nose) the
            // force along the normal and the last frame's press differ by far more than the friction limit, and
            // counted as push that difference would make the slip tens of metres a second and the friction thousands
            // of times weaker than Coulomb's.
            const Real limit = settings.frictionOf(plane.obstacle) * press;
            const Vec3& force = p.force[i];
            const Real push = (force - force.dot(plane.normal) * plane.normal).norm();
            const Real slip =
                std::max({(relative - relative.dot(plane.normal) * plane.normal).norm(),
                          dt * std::max(Real(0), push - limit) * p.inverseMass[i], settings.slipRegularization});
            damping = limit / slip;
        }
        m_constraint[i] = context.constraints.size();
        m_plane[i] = k;
        context.constraints.push_back({i, 1, plane.normal, plane.velocity, damping, Vec3::Zero()});
        context.constraints.back().friction = damping > 0 ? settings.frictionOf(plane.obstacle) : Real(0);
        m_resting[i] = 1;
        m_restingMasses.push_back(i);
        m_normal[i] = plane.normal;
        m_velocity[i] = plane.velocity;
        m_obstacle[i] = plane.obstacle;
        m_face[i] = plane.face;
    }
    // A mass near a surface it does not touch yet (none rests or is stuck; the first such plane of each) may arrive
    // there during the frame: if the solve finds it would pass through, it arrives at the surface at the frame's end
    // instead, inside the solve, so the masses joined to it stop with it. Left to the projection after the solve, a
    // sheet that moves farther than its thickness in one frame (a 2 mm PET sheet with layers 10 mm apart falling
    // 18 mm at dt = 0.03 s) has every layer put on the surface: it is squashed flat, its glassy cross-layer springs
    // hold joules, and it flies apart later. A sticky surface keeps the projection, which sticks the mass as it
    // touches.
    for (std::size_t k = 0; k < planes.size(); ++k)
    {
        const ContactPlane plane = planes[k];
        const Index i = plane.mass;
        if (stuck.stuck[i] || m_resting[i] || m_arriving[i] || p.pinned[i] ||
            settings.responseOf(plane.obstacle) == ContactResponse::Sticky)
        {
            continue;
        }
        const Real separation = plane.separation(p.position[i], settings.radius);
        if (separation < touchTolerance)
        {
            continue; // touching, but not resting: the projection's
        }
        m_constraint[i] = context.constraints.size();
        m_plane[i] = k;
        VelocityConstraint arrival{i, 1, plane.normal, plane.velocity - (separation / dt) * plane.normal};
        arrival.speculative = true;
        arrival.gap = separation - dt * plane.velocity.dot(plane.normal);
        context.constraints.push_back(arrival);
        m_arriving[i] = 1;
        m_arrivingMasses.push_back(i);
        m_obstacle[i] = plane.obstacle;
    }
}

void ContactConstraints::afterSubstep(const Particles& p, const StepContext& context, const StuckContacts& stuck,
                                      Real h, Real time, ContactReport& report)
{
    // Resting masses were handled inside the implicit solve: their contact impulse is the solve's reaction plus the
    // friction it applied as a damping.
    for (const Index i : m_restingMasses)
    {
        if (stuck.stuck[i])
        {
            continue;
        }
        const VelocityConstraint& resting = context.constraints[m_constraint[i]];
        m_lastReaction[i] = resting.reaction;
        if (resting.released)
        {
            continue; // leaving its surface within the step (ImplicitSolve::releaseLifting): no push, no friction
        }
        const Vec3 relative = p.velocity[i] - m_velocity[i];
        const Vec3 slip = relative - relative.dot(m_normal[i]) * m_normal[i];
        // The reaction holds; friction drags (with the damping the solve used, which it may have capped).
        report.addImpulse(i, m_lastReaction[i] - h * resting.tangentialDamping * slip);
        report.touch(i, m_obstacle[i], m_face[i], time);
    }
    // Masses that arrived at their surface in the solve: the projection gives their impact its friction, and its
    // touch.
    for (const Index i : m_arrivingMasses)
    {
        const VelocityConstraint& arrival = context.constraints[m_constraint[i]];
        m_arrived[i] = arrival.engaged ? 1 : 0;
        m_arrivalImpulse[i] = arrival.engaged ? arrival.reaction.dot(arrival.normal) : Real(0);
        report.addImpulse(i, arrival.reaction);
    }
}
} // namespace masse
