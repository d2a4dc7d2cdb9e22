// The contact's constraints for the implicit solve (core/contact/ContactConstraints.h): a mass that a surface
// advancing into the sheet caught in the last frame rests on it in the next, although its springs pull it away; a
// mass left on a still or receding surface with the same pull does not. A mass pressed on a surface in the last frame
// and found a little off it (sliding over a curved surface) still rests on it; one that was not pressed, or is farther,
// does not.

#include "core/contact/ContactConstraints.h"
#include "core/StepContext.h"
#include "core/contact/ContactPlanes.h"
#include "core/contact/ContactReport.h"
#include "core/contact/StuckContacts.h"

#include <gtest/gtest.h>

#include <vector>

using namespace masse;

namespace
{
/// One free mass of 1 kg and a frictionless plane whose normal is +y, moving along its normal: a plug's nose and a
/// mass of the sheet it pushes.
struct OneMassOnAPlane
{
    Particles particles;
    ContactPlanes planes;
    StuckContacts stuck;
    ContactSettings settings;
    ContactConstraints constraints;
    ContactReport report;

    OneMassOnAPlane()
    {
        particles.add(Vec3::Zero(), 1);
        settings.radius = 0.002;
        settings.response = ContactResponse::Frictionless;
        stuck.resize(1);
        constraints.resize(1);
        report.beginFrame(1, 1);
    }

    /// Detection at a frame's start: the plane as it is now (at height `surface`), then the frame's constraints.
    StepContext beginFrame(Real surface, Real surfaceSpeed, Real dt)
    {
        planes.lists().resize(1);
        planes.lists()[0].clear();
        ContactPlane plane;
        plane.mass = 0;
        plane.obstacle = 0;
        plane.face = 0;
        plane.normal = Vec3::UnitY();
        plane.offset = surface;
        plane.velocity = Vec3(0, surfaceSpeed, 0);
        planes.lists()[0].push_back(plane);
        planes.index();
        StepContext context;
        constraints.beginFrame(particles, planes, stuck, settings, dt, true, context);
        return context;
    }
};
} // namespace

TEST(ContactConstraints, AMassAnAdvancingSurfaceCaughtLastFrameRestsOnIt)
{
    const Real dt = 0.01;
    for (const Real surfaceSpeed : {Real(0.05), Real(0), Real(-0.05)})
    {
        OneMassOnAPlane rig;
        Particles& p = rig.particles;
        // Frame 1: the mass is 1 mm above the surface, still; the surface comes up at surfaceSpeed.
        p.position[0] = Vec3(0, rig.settings.radius + 0.001, 0);
        p.velocity[0] = Vec3::Zero();
        p.force[0] = Vec3(0, 5, 0); // springs pulling it up, away from the surface
        StepContext first = rig.beginFrame(0, surfaceSpeed, dt);
        ASSERT_EQ(first.constraints.size(), 1u);
        EXPECT_TRUE(first.constraints[0].speculative);
        // The solve finds that the frame would carry the surface through the mass: the constraint holds, with an
        // impulse of 0.2 N s.
        first.constraints[0].engaged = true;
        first.constraints[0].reaction = Vec3(0, 0.2, 0);
        rig.constraints.afterSubstep(p, first, rig.stuck, dt, dt, rig.report);
        ASSERT_TRUE(rig.constraints.arrived(0));

        // Frame 2: the mass touches the surface and moves with it, still pulled away by its springs.
        const Real surface = surfaceSpeed * dt;
        p.position[0] = Vec3(0, surface + rig.settings.radius, 0);
        p.velocity[0] = Vec3(0, surfaceSpeed, 0);
        const StepContext second = rig.beginFrame(surface, surfaceSpeed, dt);
        if (surfaceSpeed > 0)
        {
            // The surface presses it with the impulse that stopped it: it rests, a one-direction constraint, not
            // a speculative arrival the solve would engage again.
            ASSERT_EQ(second.constraints.size(), 1u);
            EXPECT_FALSE(second.constraints[0].speculative);
            EXPECT_EQ(second.constraints[0].directions, 1);
            EXPECT_TRUE(rig.constraints.resting(0));
        }
        else
        {
            // Nothing presses it in: its springs lift it off (left to the projection, no constraint).
            EXPECT_TRUE(second.constraints.empty()) << "surface speed " << surfaceSpeed;
            EXPECT_FALSE(rig.constraints.resting(0)) << "surface speed " << surfaceSpeed;
        }
    }
}

// A mass that slides over a plug's nose (radius R) along the tangent plane of the last frame ends the frame off the
// surface by about s^2 / 2R for a slide s: 30 um for 2.5 mm over 10 mm (the plug-assist cup's stroke finds gaps up to
// 32 um), its normal speed the surface's, as the solve held it. Pressed on the surface in the last frame, it rests
// there again; left to arrive again it would be engaged in a later round of the solve every frame. One that the surface
// pulled in the last frame (its reaction negative), that is moving off, or that is farther than 5% of the contact
// radius (0.1 mm here) does not rest. Had the frame taken every mass off its surface as apart, the first case fails.
TEST(ContactConstraints, AMassPressedLastFrameAndSlightlyOffACurvedSurfaceStillRestsOnIt)
{
    const Real dt = 0.01;
    struct Case
    {
        Real lastReaction; ///< N s along the normal, in the last frame
        Real gap;          ///< m, off the surface at the frame's start
        Real normalSpeed;  ///< m/s, away from the surface
        bool rests;
    };
    for (const Case c : {Case{0.2, 30e-6, 0, true}, Case{0.2, 0, 0, true}, Case{-0.2, 30e-6, 0, false},
                         Case{0.2, 30e-6, 0.01, false}, Case{0.2, 0.15e-3, 0, false}})
    {
        SCOPED_TRACE(testing::Message() << "reaction " << c.lastReaction << ", gap " << c.gap << ", speed "
                                        << c.normalSpeed);
        OneMassOnAPlane rig;
        Particles& p = rig.particles;
        // Frame 1: the mass rests on the still surface, which pushes it with `lastReaction`.
        p.position[0] = Vec3(0, rig.settings.radius, 0);
        p.velocity[0] = Vec3::Zero();
        p.force[0] = Vec3(0, -5, 0); // its weight and springs press it in
        StepContext first = rig.beginFrame(0, 0, dt);
        ASSERT_EQ(first.constraints.size(), 1u);
        ASSERT_FALSE(first.constraints[0].speculative);
        first.constraints[0].reaction = Vec3(0, c.lastReaction, 0);
        rig.constraints.afterSubstep(p, first, rig.stuck, dt, dt, rig.report);

        // Frame 2: it slid, and is found off the surface (moving off it in one case); its forces still press it in.
        p.position[0] = Vec3(0.0025, rig.settings.radius + c.gap, 0);
        p.velocity[0] = Vec3(0.25, c.normalSpeed, 0);
        const StepContext second = rig.beginFrame(0, 0, dt);
        ASSERT_EQ(second.constraints.size(), 1u);
        EXPECT_EQ(rig.constraints.resting(0), c.rests);
        EXPECT_EQ(second.constraints[0].speculative, !c.rests);
    }
}

// Friction, for a resting mass pushed along its surface beyond mu times its press: the solve holds it as a damping
// c = mu press / slip, sized for the slip that the push's excess gives the mass within the frame, dt (F_t - mu press) /
// m, so that at that slip the friction force is Coulomb's, mu press. The push is the force along the surface: on a
// still surface pressing the mass less than its forces press it in (F_n = -30 N against a press of 20 N), and on a
// surface advancing into it, caught last frame, whose springs pull it off (F_n = +5 N, as on a plug's nose), the normal
// difference is no push. With |F + press n| as the push the slip would be 0.056 and 0.18 m/s here and the friction 3
// and 9 times weaker than Coulomb's (tens of metres a second and thousands of times on the plug-assist cup's nose).
// With a push within mu press, the slip is the regularisation speed.
TEST(ContactConstraints, FrictionIsSizedFromThePushAlongTheSurface)
{
    const Real dt = 0.01;
    const Real mu = 0.5;
    struct Case
    {
        Real surfaceSpeed;
        Real tangential; ///< N, the force along the surface
        Real normal;     ///< N, the force along the normal in the second frame
    };
    for (const Case c : {Case{0, 12, -30}, Case{0.05, 12, 5}, Case{0, 6, -30}})
    {
        SCOPED_TRACE(testing::Message() << "surface speed " << c.surfaceSpeed << ", push " << c.tangential);
        OneMassOnAPlane rig;
        rig.settings.response = ContactResponse::Friction;
        rig.settings.friction = mu;
        Particles& p = rig.particles;
        const Real press = 20; // N: the last frame's reaction over dt
        Real surface = 0;
        if (c.surfaceSpeed > 0)
        {
            // Frame 1: the advancing surface catches the mass, 1 mm in front of it, with 0.2 N s.
            p.position[0] = Vec3(0, rig.settings.radius + 0.001, 0);
            p.force[0] = Vec3(0, 5, 0);
            StepContext first = rig.beginFrame(0, c.surfaceSpeed, dt);
            ASSERT_EQ(first.constraints.size(), 1u);
            first.constraints[0].engaged = true;
            first.constraints[0].reaction = Vec3(0, press * dt, 0);
            rig.constraints.afterSubstep(p, first, rig.stuck, dt, dt, rig.report);
            surface = c.surfaceSpeed * dt;
        }
        else
        {
            // Frame 1: it rests on the still surface, pressed with 0.2 N s.
            p.position[0] = Vec3(0, rig.settings.radius, 0);
            p.force[0] = Vec3(0, -press, 0);
            StepContext first = rig.beginFrame(0, 0, dt);
            ASSERT_EQ(first.constraints.size(), 1u);
            first.constraints[0].reaction = Vec3(0, press * dt, 0);
            rig.constraints.afterSubstep(p, first, rig.stuck, dt, dt, rig.report);
        }
        // Frame 2: on the surface, moving with it, at rest along it, pushed along it.
        p.position[0] = Vec3(0, surface + rig.settings.radius, 0);
        p.velocity[0] = Vec3(0, c.surfaceSpeed, 0);
        p.force[0] = Vec3(c.tangential, c.normal, 0);
        const StepContext second = rig.beginFrame(surface, c.surfaceSpeed, dt);
        ASSERT_EQ(second.constraints.size(), 1u);
        ASSERT_FALSE(second.constraints[0].speculative);
        const Real limit = mu * press;
        const Real slip = std::max(dt * (c.tangential - limit) / p.mass[0], rig.settings.slipRegularization);
        EXPECT_NEAR(second.constraints[0].tangentialDamping, limit / slip, 1e-9 * limit / slip);
    }
}
