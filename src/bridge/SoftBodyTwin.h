#pragma once
/// The same sheet in Bullet: one btSoftBody with a node per MaSSE mass and a link per MaSSE spring, among the same
/// obstacles, stepped with the same dt, so MaSSE's results can be set beside a widely used engine's.
///
/// Node i is mass i (same position, velocity and mass; a pinned mass becomes a node of mass 0, which Bullet never
/// moves) and link j is spring j (same two masses and rest length). The obstacles are the BulletEnvironment's own
/// collision shapes, shared, not rebuilt, each in a mass-0 btRigidBody: static, or kinematic and posed along its
/// KinematicPath at the end of every Bullet substep, so Bullet derives its velocity from the pose change. The room's
/// walls are obstacles like any other. The environment must outlive the twin.
///
/// What Bullet cannot say the same way is listed by notes(): each note names the scene key it concerns and what the
/// twin does instead. Options it cannot represent at all throw InputError from the constructor.

#include "KinematicPath.h"
#include "SoftBodyTwinSettings.h"

#include "core/MassSpringSystem.h"
#include "core/NumericalError.h"
#include "core/contact/Contact.h"

#include <memory>
#include <string>
#include <vector>

class btSoftBody;

namespace masse::bridge
{
class BulletEnvironment;

/// How the twin differs from the MaSSE scene on one point.
struct TwinNote
{
    std::string subject; ///< the scene key or topic, e.g. "contact.response"
    std::string message; ///< what Bullet does instead, in one or two sentences
};

class SoftBodyTwin
{
public:
    /// Builds the twin of `sheet` as it is now (positions, velocities, pins, spring coefficients, user springs,
    /// external forces) among the obstacles of `environment`, to be stepped by `dt` seconds. `contact` gives the
    /// contact radius and response the twin imitates. Throws InputError for bad settings, a non-positive dt, a
    /// non-finite state, or a spring joining a mass to itself.
    SoftBodyTwin(const MassSpringSystem& sheet, const BulletEnvironment& environment, const ContactSettings& contact,
                 Real dt, const SoftBodyTwinSettings& settings = {});
    ~SoftBodyTwin();
    SoftBodyTwin(const SoftBodyTwin&) = delete;
    SoftBodyTwin& operator=(const SoftBodyTwin&) = delete;

    /// Advances by dt (settings.substeps Bullet steps). Throws NumericalError if a node's state stops being finite.
    void step();

    const std::vector<TwinNote>& notes() const { return m_notes; }
    /// The settings in use, with every unset field filled in except kLST when links differ (see linkStiffness).
    const SoftBodyTwinSettings& settings() const { return m_settings; }
    Real dt() const { return m_dt; }
    Real substep() const { return m_dt / Real(m_settings.substeps); }
    Real time() const { return Real(m_substepCount) * substep(); }

    std::size_t nodeCount() const;
    std::size_t linkCount() const;
    Vec3 position(Index node) const;
    Vec3 velocity(Index node) const;
    std::vector<Vec3> positions() const;
    std::vector<Vec3> velocities() const;
    /// kg, 0 for a pinned mass.
    Real nodeMass(Index node) const;
    /// Link j's two nodes and rest length (m), as Bullet holds them.
    SpringEnds linkEnds(std::size_t link) const;
    Real linkRestLength(std::size_t link) const;
    /// Link j's kLST.
    Real linkStiffness(std::size_t link) const;

    /// Obstacle each node touched during the last step (any of its substeps), or -1; from Bullet's rigid contacts.
    const std::vector<int>& touchingObstacle() const { return m_touchObstacle; }
    std::size_t touchingCount() const;
    /// J, of the free nodes.
    Real kineticEnergy() const;
    /// Wall-clock seconds the last step took inside Bullet.
    double lastStepWallSeconds() const { return m_lastWall; }

    /// Replaces the sheet's dynamic springs by `springs`, whose targets are where they are at simulated time
    /// `aimedAt` (s); call it between steps as MaSSE's are changed. They act on the nodes as forces at the start of
    /// every substep, and a target moves on at its targetVelocity from the time it was aimed, so a target aimed once
    /// per frame is where a script aiming it every substep would put it.
    void setUserSprings(const UserSprings& springs, Real aimedAt);

    /// Changes between steps that a scene's script makes (see scene/Comparison.h): gravity (m/s^2, for the world and
    /// the soft body alike); a pin, which makes the node's mass 0 (Bullet never moves it) and stops it where it is,
    /// or an unpin, which gives it its sheet mass back; a kinematic obstacle's path (a scripted move), by the
    /// obstacle's index in the environment the twin was built from.
    void setGravity(const Vec3& gravity);
    Vec3 gravity() const;
    void setPinned(Index node, bool pinned);
    bool pinned(Index node) const;
    void setObstaclePath(int obstacle, const std::vector<PoseKey>& keys);

private:
    struct Bullet;
    struct Obstacle;

    void buildObstacles(const BulletEnvironment& environment);
    void poseKinematic(Real time);
    void applyForces();
    void collectContacts();
    void checkFinite() const;

    SoftBodyTwinSettings m_settings;
    Real m_dt;
    std::vector<TwinNote> m_notes;
    std::unique_ptr<Bullet> m_bullet;
    btSoftBody* m_body = nullptr; ///< owned by m_bullet
    std::vector<Vec3> m_externalForce;
    std::vector<Real> m_sheetMass; ///< kg, each mass as the sheet has it (given back to a node on unpinning)
    UserSprings m_userSprings;
    Real m_userSpringsAimedAt = 0;
    std::vector<int> m_touchObstacle;
    std::uint64_t m_substepCount = 0;
    double m_lastWall = 0;
};
} // namespace masse::bridge
