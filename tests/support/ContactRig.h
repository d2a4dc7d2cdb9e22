#pragma once
// A sheet, a Bullet environment and a contact solver wired to a simulator, for contact tests.

#include "support/TestSystems.h"

#include "bridge/BulletEnvironment.h"
#include "scene/ObstacleSpec.h"
#include "scene/shapes/BoxShape.h"

#include "core/Simulator.h"
#include "core/contact/ContactSolver.h"
#include "core/forces/Damping.h"
#include "core/lattice/Lattice.h"

#include <memory>

namespace masse::test
{
struct ContactRig
{
    bridge::BulletEnvironment environment;
    std::unique_ptr<ContactSolver> contact;
    std::unique_ptr<Simulator> simulator;

    void start(MassSpringSystem sheet, IntegratorKind integrator, const ContactSettings& settings)
    {
        contact = std::make_unique<ContactSolver>(environment, settings);
        SimulatorSettings simulatorSettings;
        simulatorSettings.integrator = integrator;
        simulator = std::make_unique<Simulator>(std::move(sheet), simulatorSettings);
        simulator->setContactSolver(contact.get());
    }
    Particles& particles() { return simulator->system().particles; }
};

inline bridge::ObstacleBody makeBox(const std::string& name, const Vec3& centre, const Vec3& half,
                                    const Vec3& rotationDegrees = Vec3::Zero())
{
    bridge::ObstacleBody box;
    box.name = name;
    box.shape = scene::boxSolid(half);
    box.path.rest = {centre, scene::rotationFromDegrees(rotationDegrees)};
    return box;
}

/// Exact signed distance from a point to a box (negative inside), independent of Bullet.
inline Real boxDistance(const Vec3& p, const bridge::ObstacleBody& box)
{
    const Vec3 local = box.path.rest.orientation.conjugate() * (p - box.path.rest.position);
    const Vec3 half = box.shape.polygons.vertices.back(); // the (+x, +y, +z) corner
    const Vec3 q = local.cwiseAbs() - half;
    return q.cwiseMax(0.0).norm() + std::min(q.maxCoeff(), 0.0);
}

} // namespace masse::test
