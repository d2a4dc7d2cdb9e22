// Contact between sheets and obstacles: resting, Coulomb friction, sticking, no tunnelling, reports.

#include "scene/Room.h"
#include "support/ContactRig.h"
#include "support/TestSystems.h"
#include "support/TestThreads.h"

#include "core/StepContext.h"
#include "core/contact/ContactReport.h"
#include "core/contact/ContactSolver.h"
#include "core/forces/Energy.h"
#include "core/parallel/TaskPool.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <numbers>

using namespace masse;
using namespace masse::test;

namespace
{
const IntegratorKind contactIntegrators[] = {IntegratorKind::SymplecticEuler, IntegratorKind::ImplicitEuler,
                                             IntegratorKind::Bdf2};

/// A long box tilted by `angle` degrees about z (its top face slopes down toward +x), and a small 4x2x4 sheet lying
/// on that face: built flat at the origin, turned and lifted so its bottom masses just touch it.
void startOnSlope(ContactRig& rig, Real angle, const ContactSettings& settings, IntegratorKind kind)
{
    rig.environment.addObstacle(makeBox("slope", Vec3(0, 0, 0), Vec3(20, 0.5, 2), Vec3(0, 0, -angle)));
    LatticeSpec spec;
    spec.countX = 4;
    spec.countZ = 4;
    spec.minCorner = Vec3(-0.25, 0.0, -0.25);
    spec.maxCorner = Vec3(0.25, 0.05, 0.25);
    MassSpringSystem sheet = makeSheet(buildLattice(spec), SheetParams{});
    const auto turn = scene::rotationFromDegrees(Vec3(0, 0, -angle));
    for (Vec3& x : sheet.particles.position)
    {
        x = turn * x + turn * Vec3::UnitY() * (0.5 + settings.radius);
    }
    rig.start(std::move(sheet), kind, settings);
}
} // namespace

// A Table 1 sheet dropped on a box comes to rest on it, and no mass's sphere ever ends a step inside the box by more
// than 1% of the lattice spacing (measured with the closed-form box distance, not Bullet's).
TEST(Contact, SheetDroppedOnBoxComesToRestOnIt)
{
    for (IntegratorKind kind : contactIntegrators)
    {
        ContactRig rig;
        const bridge::ObstacleBody box = makeBox("box", Vec3(0.3, -1.0, 0.3), Vec3(1.0, 0.5, 1.0));
        rig.environment.addObstacle(box);
        Lattice lattice;
        ContactSettings settings;
        rig.start(paperSheet(8, &lattice), kind, settings);
        const Real allowed = 0.01 * std::min(lattice.spacingX, lattice.spacingZ);
        Real deepest = 0;
        simulate(*rig.simulator, 4.0, paperTimeStep,
                 [&](const Simulator& s)
                 {
                     for (const Vec3& x : s.system().particles.position)
                     {
                         deepest = std::max(deepest, settings.radius - boxDistance(x, box));
                     }
                 });
        EXPECT_LE(deepest, allowed) << integratorName(kind);
        EXPECT_LT(kineticEnergy(rig.particles()), 1e-6) << integratorName(kind);
        // Resting on the top face (y = -0.5): the bottom layer sits one radius above it.
        for (Index i = 0; i < lattice.layerStart[1]; ++i)
        {
            EXPECT_NEAR(rig.particles().position[i].y(), -0.5 + settings.radius, allowed) << integratorName(kind);
        }
        EXPECT_LE(rig.contact->maxPenetration(rig.simulator->system()), allowed);
    }
}

// Coulomb friction: a sheet on a slope of angle a slides with acceleration g (sin a - mu cos a), within 2%.
TEST(Contact, SheetSlidesDownSlopeAtCoulombAcceleration)
{
    const Real angle = 30.0;
    const Real mu = 0.3;
    const Real a = angle * std::numbers::pi / 180.0;
    const Real expected = standardGravity * (std::sin(a) - mu * std::cos(a));
    for (IntegratorKind kind : contactIntegrators)
    {
        ContactRig rig;
        ContactSettings settings;
        settings.friction = mu;
        startOnSlope(rig, angle, settings, kind);
        const auto turn = scene::rotationFromDegrees(Vec3(0, 0, -angle));

        auto along = [&]
        {
            Vec3 centre = Vec3::Zero();
            for (const Vec3& x : rig.particles().position)
            {
                centre += x / Real(rig.particles().size());
            }
            return centre.dot(turn * Vec3::UnitX());
        };
        // Let the sheet settle onto the surface for a moment, then time the slide from there.
        simulate(*rig.simulator, 0.3, 0.01, [](const Simulator&) {});
        const Real t0 = rig.simulator->time();
        const Real s0 = along();
        Real v0 = 0;
        for (std::size_t i = 0; i < rig.particles().size(); ++i)
        {
            v0 += rig.particles().velocity[i].dot(turn * Vec3::UnitX()) / Real(rig.particles().size());
        }
        simulate(*rig.simulator, 1.0, 0.01, [](const Simulator&) {});
        const Real t = rig.simulator->time() - t0;
        const Real measured = 2 * (along() - s0 - v0 * t) / (t * t);
        EXPECT_NEAR(measured, expected, 0.02 * expected) << integratorName(kind);
    }
}

// With mu above tan(a) the sheet stays put on the slope.
TEST(Contact, SheetStaysOnSlopeWhenFrictionExceedsTangent)
{
    const Real angle = 30.0;
    ContactRig rig;
    ContactSettings settings;
    settings.friction = 0.7; // tan 30 = 0.577
    startOnSlope(rig, angle, settings, IntegratorKind::SymplecticEuler);
    const std::vector<Vec3> start = rig.particles().position;
    simulate(*rig.simulator, 1.5, 0.01, [](const Simulator&) {});
    for (std::size_t i = 0; i < start.size(); ++i)
    {
        EXPECT_LT((rig.particles().position[i] - start[i]).norm(), 1e-3);
    }
}

// Sticky contact (the paper's): a soft sheet dropped half over a narrow post. Once a mass touches, it does not move
// (bit for bit), while the part beyond the post's edge keeps falling and hangs down.
TEST(Contact, StickyContactHoldsContactedMasses)
{
    for (IntegratorKind kind : contactIntegrators)
    {
        ContactRig rig;
        rig.environment.addObstacle(makeBox("post", Vec3(0.0, -0.5, 0.3), Vec3(0.25, 0.5, 1.0)));
        ContactSettings settings;
        settings.response = ContactResponse::Sticky;
        LatticeSpec spec;
        spec.countX = 8;
        spec.countZ = 8;
        SheetParams soft; // a sheet soft enough to drape: 2 N/m springs, 1 g masses
        soft.springClasses[0].stiffness = 2.0;
        soft.springClasses[1].stiffness = 2.0;
        MassSpringSystem sheet = makeSheet(buildLattice(spec), soft);
        sheet.forces.airDamping = airDampingRate(paperAirRetention, paperTimeStep);
        rig.start(std::move(sheet), kind, settings);
        std::vector<Vec3> stuckAt(rig.particles().size(), Vec3::Constant(std::nan("")));
        int checked = 0;
        simulate(*rig.simulator, 2.0, paperTimeStep,
                 [&](const Simulator& s)
                 {
                     const Particles& p = s.system().particles;
                     for (std::size_t i = 0; i < p.size(); ++i)
                     {
                         if (!rig.contact->stuck()[i])
                         {
                             continue;
                         }
                         if (!stuckAt[i].allFinite())
                         {
                             stuckAt[i] = p.position[i];
                         }
                         EXPECT_EQ(p.position[i], stuckAt[i]) << "mass " << i << " moved while stuck";
                         ++checked;
                     }
                 });
        EXPECT_GT(checked, 100) << integratorName(kind);
        // The part beyond the post (x > 0.25) hangs well below the post's top (y = 0).
        Real lowest = 1e9;
        for (const Vec3& x : rig.particles().position)
        {
            lowest = std::min(lowest, x.y());
        }
        EXPECT_LT(lowest, -0.2) << integratorName(kind);
    }
}

// A sheet thrown at 50 m/s covers 1.5 m per 0.03 s step, far more than a 1 cm thick plate: it must not pass through.
TEST(Contact, FastSheetDoesNotTunnelThroughThinPlate)
{
    for (IntegratorKind kind : contactIntegrators)
    {
        ContactRig rig;
        const bridge::ObstacleBody plate = makeBox("plate", Vec3(0.3, -1.0, 0.3), Vec3(2.0, 0.005, 2.0));
        rig.environment.addObstacle(plate);
        MassSpringSystem sheet = paperSheet(6);
        for (Vec3& v : sheet.particles.velocity)
        {
            v = Vec3(0, -50, 0);
        }
        ContactSettings settings;
        settings.response = ContactResponse::Frictionless;
        rig.start(std::move(sheet), kind, settings);
        simulate(*rig.simulator, 0.6, paperTimeStep,
                 [&](const Simulator& s)
                 {
                     for (const Vec3& x : s.system().particles.position)
                     {
                         ASSERT_GT(x.y(), -1.0 + 0.005) << integratorName(kind) << " at t = " << s.time();
                     }
                 });
        EXPECT_TRUE(rig.contact->report().everTouched(0));
    }
}

// The paper's sheet dropped from Table 1's height onto the room floor at dt = 0.03 stays above it.
TEST(Contact, SheetDoesNotFallThroughTheFloorAtPaperStep)
{
    for (IntegratorKind kind : {IntegratorKind::ExplicitEuler, IntegratorKind::SymplecticEuler,
                                IntegratorKind::VelocityVerlet, IntegratorKind::ImplicitEuler})
    {
        ContactRig rig;
        scene::addRoom(rig.environment, scene::RoomSpec{});
        Lattice lattice;
        ContactSettings settings;
        rig.start(paperSheet(6, &lattice), kind, settings);
        const Real allowed = 0.01 * lattice.spacingX;
        simulate(*rig.simulator, 2.0, paperTimeStep,
                 [&](const Simulator& s)
                 {
                     for (const Vec3& x : s.system().particles.position)
                     {
                         ASSERT_GE(x.y(), -2.81 + settings.radius - allowed) << integratorName(kind);
                     }
                 });
        EXPECT_TRUE(rig.contact->report().everTouched(rig.environment.findObstacle("floor"))) << integratorName(kind);
    }
}

// A sheet that one implicit step carries farther than its thickness lands as a sheet: its lower layer arrives at the
// box inside the solve and stops the upper one, which stays a layer's height above it. Left to the projection after
// the step, both layers were put on the box: the sheet was squashed flat (issue 15's grab on a hot table).
TEST(Contact, ImplicitLandingKeepsTheSheetsLayersApart)
{
    ContactRig rig;
    ContactSettings settings;
    rig.environment.addObstacle(makeBox("table", Vec3(0, -0.5, 0), Vec3(1, 0.5, 1)));
    LatticeSpec spec;
    spec.countX = 4;
    spec.countZ = 4;
    const Real gap = 0.01; // between the layers
    const Real above = 0.002;
    spec.minCorner = Vec3(-0.02, settings.radius + above, -0.02);
    spec.maxCorner = Vec3(0.02, settings.radius + above + gap, 0.02);
    const Lattice lattice = buildLattice(spec);
    // Stiff, with the masses as far apart across the sheet as its layers: the inter-layer springs hold the layers
    // apart (a wide, soft sheet's nearly flat inter-layer springs would let the upper layer through).
    SheetParams stiff;
    for (SpringClassParams& c : stiff.springClasses)
    {
        c.stiffness = 1e5;
    }
    MassSpringSystem sheet = makeSheet(lattice, stiff);
    for (Vec3& v : sheet.particles.velocity)
    {
        v = Vec3(0, -1, 0); // 30 mm in a step of 0.03 s: through the gap and the layers' spacing
    }
    rig.start(std::move(sheet), IntegratorKind::ImplicitEuler, settings);
    rig.simulator->step(paperTimeStep);
    const Particles& p = rig.particles();
    for (Index i = 0; i < lattice.layerStart[1]; ++i)
    {
        EXPECT_NEAR(p.position[i].y(), settings.radius, 1e-9) << "lower layer, mass " << i;
        EXPECT_LE(std::abs(p.velocity[i].y()), 1e-9) << "lower layer, mass " << i;
    }
    for (Index i = lattice.layerStart[1]; i < p.size(); ++i)
    {
        EXPECT_GT(p.position[i].y(), settings.radius + 0.5 * gap) << "upper layer, mass " << i;
    }
    EXPECT_TRUE(rig.contact->report().everTouched(0));
}

// Reports: a sheet landing flat on a box touches the box's top face (face 2) and nothing else; its first contact is
// recorded once, at the time of landing.
TEST(Contact, ReportsNameTheBoxAndItsTopFace)
{
    ContactRig rig;
    scene::addRoom(rig.environment, scene::RoomSpec{});
    const int box = rig.environment.addObstacle(makeBox("box", Vec3(0.3, -1.0, 0.3), Vec3(1.0, 0.5, 1.0)));
    rig.start(paperSheet(6), IntegratorKind::ImplicitEuler, ContactSettings{});
    simulate(*rig.simulator, 3.0, paperTimeStep, [](const Simulator&) {});
    ASSERT_EQ(rig.contact->report().firstContacts().size(), 1u);
    EXPECT_EQ(rig.contact->report().firstContacts()[0].obstacle, box);
    // Falling 0.8 m - radius from rest: t = sqrt(2 h / g) = 0.40 s; allow a frame and the air's drag.
    EXPECT_NEAR(rig.contact->report().firstContacts()[0].time, std::sqrt(2 * (0.79) / standardGravity), 0.04);
    ASSERT_EQ(rig.contact->report().touchedFaces().size(), 1u);
    EXPECT_EQ(rig.contact->report().touchedFaces()[0], std::make_pair(box, 2));
    std::size_t touching = 0;
    for (int obstacle : rig.contact->report().touchingObstacle())
    {
        touching += obstacle == box ? 1 : 0;
    }
    EXPECT_EQ(touching, 36u); // the whole 6 x 6 bottom layer
    // Contact forces carry the sheet's weight (61 g).
    Vec3 total = Vec3::Zero();
    for (const Vec3& f : rig.contact->report().contactForce())
    {
        total += f;
    }
    EXPECT_NEAR(total.y(), 61 * 0.001 * standardGravity, 0.01 * 61 * 0.001 * standardGravity);
}

// The frame's report, summed over chunks of masses on the threads: the touching count, the touched (obstacle, face)
// pairs sorted and each once, and each mass's mean force (its impulse over dt), against the same computed by hand, on
// 20,000 masses (five chunks) whose touches change face every few masses and come back to earlier faces in later
// chunks, at 1 and 3 threads.
TEST(Contact, FrameReportOverChunksMatchesTheSerialOne)
{
    const std::size_t masses = 20000;
    const Real dt = 0.03;
    std::size_t expectedTouching = 0;
    std::vector<std::pair<int, int>> expectedFaces;
    for (std::size_t i = 0; i < masses; ++i)
    {
        if (i % 5 != 4)
        {
            ++expectedTouching;
            expectedFaces.emplace_back(int(i % 3), int((i / 7) % 5));
        }
    }
    std::sort(expectedFaces.begin(), expectedFaces.end());
    expectedFaces.erase(std::unique(expectedFaces.begin(), expectedFaces.end()), expectedFaces.end());
    for (const int threads : {1, 3})
    {
        const test::BoundPool pool(threads);
        ContactReport report;
        report.beginFrame(masses, 3);
        for (std::size_t i = 0; i < masses; ++i)
        {
            report.clearMass(i);
            if (i % 5 != 4)
            {
                report.touch(Index(i), int(i % 3), int((i / 7) % 5), 0.01);
                report.addImpulse(i, Vec3(Real(i), -1, 0.5));
            }
        }
        report.endFrame(dt);
        EXPECT_EQ(report.touchingCount(), expectedTouching) << threads << " threads";
        EXPECT_EQ(report.touchedFaces(), expectedFaces) << threads << " threads";
        for (std::size_t i = 0; i < masses; i += 997)
        {
            const Vec3 expected = i % 5 != 4 ? Vec3(Vec3(Real(i), -1, 0.5) * (Real(1) / dt)) : Vec3::Zero();
            EXPECT_EQ(report.contactForce()[i], expected) << "mass " << i;
        }
    }
}

namespace
{
/// Finds nothing; keeps the reach each mass was searched with.
class ReachRecorder final : public ContactDetector
{
public:
    std::vector<Real> reach;
    int obstacleCount() const override { return 1; }
    void setTime(Real /*time*/) override {}
    void findContacts(const std::vector<Vec3>& /*x*/, const std::vector<Real>& searched, Real /*radius*/, Real /*dt*/,
                      ContactPlaneLists& out) override
    {
        reach = searched;
        out.resize(1);
        out[0].clear();
    }
    std::optional<SweepHit> sweep(const Vec3& /*from*/, const Vec3& /*to*/, Real /*radius*/) override
    {
        return std::nullopt;
    }
    SurfaceDistance nearestSurface(const Vec3& /*x*/, Real maxDistance) override { return {maxDistance, -1, -1}; }
    Vec3 pointVelocity(int /*obstacle*/, const Vec3& /*point*/, Real /*dt*/) override { return Vec3::Zero(); }
};
} // namespace

// A mass's contact search reaches as far as its velocity and its force could carry it in the frame. A forming
// pressure is some 1e5 m/s^2 on a thin sheet's masses, which in a frame of 0.01 s would be a search of metres, the
// whole mould for every mass; an implicit frame is split by the motion limit long before a mass goes that far, so
// the force's share is capped at drivenReach (the velocity's share stays whole). Checked mass by mass against the
// formula, with and without the cap.
TEST(Contact, TheForcesShareOfTheSearchIsCappedAtTheDrivenReach)
{
    LatticeSpec spec;
    spec.countX = 3;
    spec.countZ = 3;
    MassSpringSystem sheet = makeSheet(buildLattice(spec), SheetParams{});
    Particles& p = sheet.particles;
    for (std::size_t i = 0; i < p.size(); ++i)
    {
        p.pinned[i] = false;
        p.velocity[i] = Vec3(0, -Real(i % 4), 0);
        p.force[i] = Vec3(0, -1e5 * p.mass[i] * Real(i % 3), 0); // 0, 1e5 and 2e5 m/s^2
    }
    sheet.forces.gravity = Vec3(0, -standardGravity, 0);
    const Real dt = 0.01;
    const Real cap = 0.012;
    for (const Real drivenReach : {Real(0), cap})
    {
        ReachRecorder detector;
        ContactSettings settings;
        settings.radius = 0.002;
        settings.drivenReach = drivenReach;
        ContactSolver solver(detector, settings);
        StepContext context;
        solver.detect(sheet, context, 0, dt, true);
        ASSERT_EQ(detector.reach.size(), p.size());
        for (std::size_t i = 0; i < p.size(); ++i)
        {
            const Real driven = (standardGravity + p.force[i].norm() / p.mass[i]) * dt * dt;
            const Real expected =
                Real(i % 4) * dt + (drivenReach > 0 ? std::min(driven, drivenReach) : driven) + settings.radius;
            EXPECT_NEAR(detector.reach[i], expected, 1e-12 * expected) << "mass " << i << ", cap " << drivenReach;
        }
        if (drivenReach > 0)
        {
            EXPECT_LT(*std::max_element(detector.reach.begin(), detector.reach.end()), 0.1); // metres uncapped
        }
    }
}
