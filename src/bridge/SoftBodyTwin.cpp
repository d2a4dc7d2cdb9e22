#include "SoftBodyTwin.h"
#include "core/Format.h"

#include "BulletEnvironment.h"
#include "BulletMath.h"
#include "StiffnessCalibration.h"

#include "core/InputError.h"
#include "core/NumericalError.h"
#include "core/Simulator.h"

#include <BulletCollision/BroadphaseCollision/btDbvtBroadphase.h>
#include <BulletCollision/CollisionDispatch/btCollisionDispatcher.h>
#include <BulletDynamics/ConstraintSolver/btSequentialImpulseConstraintSolver.h>
#include <BulletDynamics/Dynamics/btRigidBody.h>
#include <BulletSoftBody/btSoftBody.h>
#include <BulletSoftBody/btSoftBodyRigidBodyCollisionConfiguration.h>
#include <BulletSoftBody/btSoftRigidDynamicsWorld.h>

#include <chrono>
#include <cmath>
#include <map>
#include <sstream>

namespace masse::bridge
{
/// One obstacle of the environment, as a mass-0 rigid body sharing the environment's collision shape.
struct SoftBodyTwin::Obstacle
{
    KinematicPath path;
    std::unique_ptr<btRigidBody> body;
};

/// Bullet's world and everything in it. Bodies leave the world before they are deleted (btCollisionWorld's destructor
/// still reads the objects it holds), even when the twin's constructor throws half-way.
struct SoftBodyTwin::Bullet
{
    btSoftBodyRigidBodyCollisionConfiguration configuration;
    btCollisionDispatcher dispatcher{&configuration};
    btDbvtBroadphase broadphase;
    btSequentialImpulseConstraintSolver solver;
    btSoftRigidDynamicsWorld world{&dispatcher, &broadphase, &solver, &configuration};
    std::unique_ptr<btSoftBody> body;
    std::vector<std::unique_ptr<Obstacle>> obstacles;

    ~Bullet()
    {
        for (auto& obstacle : obstacles)
        {
            world.removeRigidBody(obstacle->body.get());
        }
        if (body)
        {
            world.removeSoftBody(body.get());
        }
    }
};

namespace
{
/// Largest k h^2 / mu for which the one-link formula keeps the twin's static sag within about 8% of MaSSE's
/// (StiffnessCalibrationTest measures it on the Table 1 sheet).
constexpr Real maxFormulaLoad = 0.25;

/// What the twin represents only approximately in this scene, each with the scene key it concerns.
std::vector<TwinNote> describeDifferences(const MassSpringSystem& sheet, const BulletEnvironment& environment,
                                          const ContactSettings& contact, const SoftBodyTwinSettings& settings,
                                          Real substep)
{
    std::vector<TwinNote> notes;
    notes.push_back(
        {"integrator", "MaSSE integrates spring forces in time; Bullet's classic soft body predicts positions, then "
                       "projects links and contacts " +
                           std::to_string(settings.piterations) +
                           " time(s) per substep and takes velocities from the displacement. kLST is matched to "
                           "MaSSE's springs for static stretch only, so vibration frequencies and transients differ."});
    if (!settings.kLST)
    {
        // k h^2 / mu, the load of one substep relative to a link's stiffness, for the stiffest spring.
        Real load = 0;
        const Particles& p = sheet.particles;
        for (std::size_t j = 0; j < sheet.springs.size(); ++j)
        {
            const SpringEnds e = sheet.springs.ends()[j];
            const Real inverseMass =
                (p.pinned[e.a] ? 0 : p.inverseMass[e.a]) + (p.pinned[e.b] ? 0 : p.inverseMass[e.b]);
            load = std::max(load, sheet.springs.stiffness()[j] * substep * substep * inverseMass);
        }
        if (load > maxFormulaLoad)
        {
            notes.push_back(
                {"springs.stiffness()",
                 "kLST comes from the one-link formula (StiffnessCalibration.h), which holds while "
                 "k h^2 / mu is about 0.2 or less; here it reaches " +
                     formatNumber(load) +
                     ", and Gauss-Seidel projection over the whole lattice leaves the twin softer than "
                     "MaSSE's sheet (the Table 1 sheet clamped on two edges sags 8 to 11 times as much at h = 0.03 s). "
                     "calibrateLinearStiffness measures the gap; more substeps close it."});
        }
    }
    bool dashpots = false;
    for (Real kd : sheet.springs.damping())
    {
        dashpots = dashpots || kd > 0;
    }
    if (dashpots)
    {
        notes.push_back({"springs.damping()",
                         "Bullet links have no dashpot: the springs' damping (k_d) is left out; what damps the "
                         "twin's internal motion is its projection, whose damping depends on kLST, h and "
                         "piterations, not on k_d."});
    }
    if (sheet.forces.repulsion > 0)
    {
        notes.push_back(
            {"forces.repulsion", "Bullet links resist compression exactly as they resist stretching; the compression "
                                 "repulsion k_r = " +
                                     formatNumber(sheet.forces.repulsion) + " N m^2 is left out."});
    }
    notes.push_back(
        {"contact",
         "Bullet tests nodes against obstacles only where the substep's prediction puts them (no sweep): a node that "
         "moves farther than an obstacle's thickness in one substep can pass through it. A node found within the "
         "margin loses its approach and is also lifted by kKHR = " +
             formatNumber(settings.kKHR) +
             " times its predicted depth, so it can end above where it started the substep: landings bounce and "
             "resting nodes jitter by about g h^2."});
    const Real friction = settings.kDF ? *settings.kDF : std::min(contact.friction, Real(1));
    switch (contact.response)
    {
    case ContactResponse::Sticky:
        notes.push_back({"contact.response",
                         "Bullet has no sticky contact: approximated by friction kDF = " +
                             formatNumber(settings.kDF ? *settings.kDF : Real(1)) +
                             ", so a node in contact loses (up to) all its tangential motion, but it leaves the "
                             "surface as soon as it is pulled away (no hold, no release force) and is not pinned "
                             "where it first touched."});
        break;
    case ContactResponse::Friction:
        if (friction > 0)
        {
            notes.push_back(
                {"contact.friction",
                 "Bullet's node friction is not Coulomb's: a node whose tangential motion in a substep "
                 "is below kDF = " +
                     formatNumber(friction) +
                     " times its approach stops, otherwise it loses the fraction kDF of it, whatever the "
                     "load. Sliding speeds differ from MaSSE's mu law." +
                     std::string(!settings.kDF && contact.friction > 1 ? " mu = " + formatNumber(contact.friction) +
                                                                             " is above Bullet's range [0, 1]: kDF = 1."
                                                                       : "")});
        }
        break;
    case ContactResponse::Frictionless:
        break;
    }
    if (sheet.userSprings.size() > 0)
    {
        notes.push_back({"user_springs",
                         "The dynamic (mouse) springs are applied to the nodes as forces evaluated at the start of "
                         "each Bullet substep (explicitly), where MaSSE's implicit integrator treats them "
                         "implicitly; their force cap is honoured."});
    }
    for (int i = 0; i < environment.obstacleCount(); ++i)
    {
        const bridge::Obstacle& obstacle = environment.obstacle(i);
        if (!obstacle.geometry.convex)
        {
            notes.push_back({"obstacles." + obstacle.name,
                             "Bullet meets a triangle mesh one triangle at a time, each as a convex slab extruded "
                             "0.06 m to both sides of the triangle (BT_SOFTBODY_TRIANGLE_EXTRUSION in "
                             "btSoftBodyConcaveCollisionAlgorithm.cpp): nodes stop the margin plus 0.06 m from the "
                             "mesh's surface (0.07 m for a 0.01 m margin) instead of the margin, on either side. "
                             "Contact with this obstacle is not comparable with MaSSE's."});
        }
    }
    return notes;
}

void validateSheet(const MassSpringSystem& sheet)
{
    const Particles& p = sheet.particles;
    if (p.size() == 0)
    {
        throw InputError("twin: the sheet has no masses");
    }
    for (std::size_t i = 0; i < p.size(); ++i)
    {
        if (!p.position[i].allFinite() || !p.velocity[i].allFinite() || !(p.mass[i] > 0) || !std::isfinite(p.mass[i]))
        {
            throw InputError("twin: mass " + std::to_string(i) +
                             " has a non-finite position or velocity or a non-positive mass");
        }
    }
    for (std::size_t j = 0; j < sheet.springs.size(); ++j)
    {
        const SpringEnds ends = sheet.springs.ends()[j];
        if (ends.a == ends.b || ends.a >= p.size() || ends.b >= p.size())
        {
            throw InputError("twin: spring " + std::to_string(j) +
                             " does not join two distinct masses of the sheet; a Bullet link cannot represent it");
        }
        if (!(sheet.springs.restLength()[j] >= 0) || !(sheet.springs.stiffness()[j] >= 0))
        {
            throw InputError("twin: spring " + std::to_string(j) +
                             " has a negative or non-finite rest length or "
                             "stiffness");
        }
    }
}
} // namespace

SoftBodyTwin::SoftBodyTwin(const MassSpringSystem& sheet, const BulletEnvironment& environment,
                           const ContactSettings& contact, Real dt, const SoftBodyTwinSettings& settings)
    : m_settings(settings), m_dt(dt)
{
    validate(settings);
    validate(contact);
    if (!(dt > 0) || !std::isfinite(dt))
    {
        throw InputError("twin: the time step must be a positive number of seconds (got " + formatNumber(dt) + ")");
    }
    validateSheet(sheet);
    const Real h = substep();
    m_notes = describeDifferences(sheet, environment, contact, settings, h);
    // Fill in what was left to the sheet.
    if (!m_settings.kDP)
    {
        m_settings.kDP = 1 - std::exp(-sheet.forces.airDamping * h);
    }
    if (!m_settings.kDF)
    {
        switch (contact.response)
        {
        case ContactResponse::Sticky:
            m_settings.kDF = 1;
            break;
        case ContactResponse::Friction:
            m_settings.kDF = std::min(contact.friction, Real(1));
            break;
        case ContactResponse::Frictionless:
            m_settings.kDF = 0;
            break;
        }
    }
    if (!m_settings.margin)
    {
        m_settings.margin = contact.radius;
    }

    m_bullet = std::make_unique<Bullet>();
    btSoftBodyWorldInfo& info = m_bullet->world.getWorldInfo();
    m_bullet->world.setGravity(toBullet(sheet.forces.gravity));
    info.m_gravity = toBullet(sheet.forces.gravity); // the soft body reads gravity here, not from the world
    info.m_sparsesdf.setDefaultVoxelsz(m_settings.sdfCellSize);
    info.m_sparsesdf.Reset();

    // Nodes. Built from arrays: with Debian's 3.24, appending nodes to an empty btSoftBody crashes.
    const Particles& p = sheet.particles;
    std::vector<btVector3> x(p.size());
    std::vector<btScalar> m(p.size());
    for (std::size_t i = 0; i < p.size(); ++i)
    {
        x[i] = toBullet(p.position[i]);
        m[i] = p.pinned[i] ? btScalar(0) : btScalar(p.mass[i]);
    }
    m_bullet->body = std::make_unique<btSoftBody>(&info, int(p.size()), x.data(), m.data());
    m_body = m_bullet->body.get();
    for (std::size_t i = 0; i < p.size(); ++i)
    {
        m_body->m_nodes[int(i)].m_v = p.pinned[i] ? btVector3(0, 0, 0) : toBullet(p.velocity[i]);
    }

    // Links, one per spring, with one material per distinct kLST.
    std::map<Real, btSoftBody::Material*> materials;
    auto materialFor = [&](Real kLST)
    {
        auto found = materials.find(kLST);
        if (found != materials.end())
        {
            return found->second;
        }
        btSoftBody::Material* material = materials.empty() ? m_body->m_materials[0] : m_body->appendMaterial();
        material->m_kLST = kLST;
        material->m_kAST = 1;
        material->m_kVST = 1;
        materials.emplace(kLST, material);
        return material;
    };
    const SpringSet& springs = sheet.springs;
    for (std::size_t j = 0; j < springs.size(); ++j)
    {
        const SpringEnds ends = springs.ends()[j];
        Real kLST = 1;
        if (m_settings.kLST)
        {
            kLST = *m_settings.kLST;
        }
        else
        {
            const Real inverseMass =
                p.inverseMass[ends.a] * (p.pinned[ends.a] ? 0 : 1) + p.inverseMass[ends.b] * (p.pinned[ends.b] ? 0 : 1);
            // A link between two pinned nodes is never projected; any factor will do.
            kLST = inverseMass > 0
                       ? pbdLinearStiffness(springs.stiffness()[j], 1 / inverseMass, h, m_settings.piterations)
                       : Real(1);
        }
        m_body->appendLink(int(ends.a), int(ends.b), materialFor(kLST), false);
        btSoftBody::Link& link = m_body->m_links[int(j)];
        link.m_rl = springs.restLength()[j];
        link.m_c1 = link.m_rl * link.m_rl;
    }
    if (m_settings.kLST.has_value() == false && materials.size() == 1)
    {
        m_settings.kLST = materials.begin()->first;
    }
    // appendLink asked Bullet to refresh its constants at the next step, and that refresh (updateConstants) resets
    // every rest length to the current distance between the nodes: a sheet that starts stretched would lose its rest
    // state. Refresh what it would, minus the rest lengths, and clear the request.
    m_body->updateLinkConstants();
    m_body->updateArea();
    m_body->m_bUpdateRtCst = false;

    btSoftBody::Config& cfg = m_body->m_cfg;
    cfg.kDP = *m_settings.kDP;
    cfg.kDF = *m_settings.kDF;
    cfg.kCHR = m_settings.kCHR;
    cfg.kKHR = m_settings.kKHR;
    cfg.piterations = m_settings.piterations;
    cfg.collisions = btSoftBody::fCollision::SDF_RS;
    m_body->getCollisionShape()->setMargin(*m_settings.margin);
    m_body->setActivationState(DISABLE_DEACTIVATION);
    m_bullet->world.addSoftBody(m_body);

    buildObstacles(environment);

    m_externalForce = p.externalForce;
    m_sheetMass = p.mass;
    m_userSprings = sheet.userSprings;
    m_touchObstacle.assign(p.size(), -1);
}

SoftBodyTwin::~SoftBodyTwin() = default;

void SoftBodyTwin::buildObstacles(const BulletEnvironment& environment)
{
    for (int i = 0; i < environment.obstacleCount(); ++i)
    {
        const bridge::Obstacle& source = environment.obstacle(i);
        auto obstacle = std::make_unique<Obstacle>();
        obstacle->path = source.path;
        btRigidBody::btRigidBodyConstructionInfo info(0, nullptr, source.geometry.shape.get());
        const Pose pose = poseAt(source.path, 0);
        info.m_startWorldTransform = toBullet(pose.position, pose.orientation);
        // Friction 1 so that kDF alone is the coefficient (Bullet multiplies the two).
        info.m_friction = 1;
        obstacle->body = std::make_unique<btRigidBody>(info);
        obstacle->body->setUserIndex(i);
        if (source.path.isKinematic())
        {
            obstacle->body->setCollisionFlags(obstacle->body->getCollisionFlags() |
                                              btCollisionObject::CF_KINEMATIC_OBJECT);
            obstacle->body->setActivationState(DISABLE_DEACTIVATION);
        }
        // Obstacles never meet one another (the paper's game rule), only the sheet.
        m_bullet->world.addRigidBody(obstacle->body.get(), btBroadphaseProxy::StaticFilter,
                                     btBroadphaseProxy::AllFilter ^ btBroadphaseProxy::StaticFilter);
        m_bullet->obstacles.push_back(std::move(obstacle));
    }
}

void SoftBodyTwin::poseKinematic(Real time)
{
    for (auto& obstacle : m_bullet->obstacles)
    {
        if (obstacle->path.isKinematic())
        {
            const Pose pose = poseAt(obstacle->path, time);
            obstacle->body->setWorldTransform(toBullet(pose.position, pose.orientation));
        }
    }
}

void SoftBodyTwin::applyForces()
{
    for (std::size_t i = 0; i < m_externalForce.size(); ++i)
    {
        if (!m_externalForce[i].isZero(0))
        {
            m_body->addForce(toBullet(m_externalForce[i]), int(i));
        }
    }
    // The substep starts now: a target aimed earlier has moved on along its velocity since.
    const Real elapsed = time() - m_userSpringsAimedAt;
    for (UserSpring spring : m_userSprings.all())
    {
        spring.target += elapsed * spring.targetVelocity;
        const btSoftBody::Node& node = m_body->m_nodes[int(spring.mass)];
        const UserSpringForce force = evaluateUserSpring(spring, toVec3(node.m_x), toVec3(node.m_v));
        m_body->addForce(toBullet(force.force), int(spring.mass));
    }
}

void SoftBodyTwin::collectContacts()
{
    const btSoftBody::Node* first = &m_body->m_nodes[0];
    for (int c = 0; c < m_body->m_rcontacts.size(); ++c)
    {
        const btSoftBody::RContact& contact = m_body->m_rcontacts[c];
        m_touchObstacle[std::size_t(contact.m_node - first)] = contact.m_cti.m_colObj->getUserIndex();
    }
}

void SoftBodyTwin::step()
{
    const auto start = std::chrono::steady_clock::now();
    const Real h = substep();
    std::fill(m_touchObstacle.begin(), m_touchObstacle.end(), -1);
    for (int s = 0; s < m_settings.substeps; ++s)
    {
        // Kinematic obstacles go where they are at the end of the substep; Bullet takes their velocity from the
        // change of pose (btRigidBody::saveKinematicState).
        poseKinematic(Real(m_substepCount + 1) * h);
        applyForces();
        // One Bullet step of exactly h: Bullet's own fixed-step loop keeps a floating remainder that can drop or add a
        // substep, and would move kinematic obstacles once per call rather than once per substep.
        m_bullet->world.stepSimulation(h, 0, h);
        m_bullet->world.getWorldInfo().m_sparsesdf.GarbageCollect();
        collectContacts();
        ++m_substepCount;
    }
    m_lastWall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    checkFinite();
}

void SoftBodyTwin::checkFinite() const
{
    for (int i = 0; i < m_body->m_nodes.size(); ++i)
    {
        const btSoftBody::Node& node = m_body->m_nodes[i];
        if (!toVec3(node.m_x).allFinite() || !toVec3(node.m_v).allFinite())
        {
            throw NumericalError("Bullet twin: node " + std::to_string(i) +
                                 " is not finite at t = " + formatNumber(time()) + " s");
        }
    }
}

void SoftBodyTwin::setUserSprings(const UserSprings& springs, Real aimedAt)
{
    m_userSprings = springs;
    m_userSpringsAimedAt = aimedAt;
}

void SoftBodyTwin::setGravity(const Vec3& gravity)
{
    m_bullet->world.setGravity(toBullet(gravity));
    m_bullet->world.getWorldInfo().m_gravity = toBullet(gravity);
}

Vec3 SoftBodyTwin::gravity() const
{
    return toVec3(m_bullet->world.getWorldInfo().m_gravity);
}

void SoftBodyTwin::setPinned(Index node, bool pinned)
{
    btSoftBody::Node& n = m_body->m_nodes[int(node)];
    n.m_im = pinned ? btScalar(0) : btScalar(1 / m_sheetMass[node]);
    if (pinned)
    {
        n.m_v.setZero();
    }
    // Not btSoftBody::setMass: it asks for updateConstants at the next step, which would reset every link's rest
    // length to the current distance between its nodes. Only the links' mass terms depend on the node's mass.
    m_body->updateLinkConstants();
}

bool SoftBodyTwin::pinned(Index node) const
{
    return !(m_body->m_nodes[int(node)].m_im > 0);
}

void SoftBodyTwin::setObstaclePath(int obstacle, const std::vector<PoseKey>& keys)
{
    Obstacle& o = *m_bullet->obstacles.at(std::size_t(obstacle));
    const bool wasKinematic = o.path.isKinematic();
    o.path.keys = keys;
    if (!wasKinematic && o.path.isKinematic())
    {
        o.body->setCollisionFlags(o.body->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
        o.body->setActivationState(DISABLE_DEACTIVATION);
    }
}

std::size_t SoftBodyTwin::nodeCount() const
{
    return std::size_t(m_body->m_nodes.size());
}

std::size_t SoftBodyTwin::linkCount() const
{
    return std::size_t(m_body->m_links.size());
}

Vec3 SoftBodyTwin::position(Index node) const
{
    return toVec3(m_body->m_nodes[int(node)].m_x);
}

Vec3 SoftBodyTwin::velocity(Index node) const
{
    return toVec3(m_body->m_nodes[int(node)].m_v);
}

std::vector<Vec3> SoftBodyTwin::positions() const
{
    std::vector<Vec3> out(nodeCount());
    for (std::size_t i = 0; i < out.size(); ++i)
    {
        out[i] = position(Index(i));
    }
    return out;
}

std::vector<Vec3> SoftBodyTwin::velocities() const
{
    std::vector<Vec3> out(nodeCount());
    for (std::size_t i = 0; i < out.size(); ++i)
    {
        out[i] = velocity(Index(i));
    }
    return out;
}

Real SoftBodyTwin::nodeMass(Index node) const
{
    const btScalar im = m_body->m_nodes[int(node)].m_im;
    return im > 0 ? 1 / im : 0;
}

SpringEnds SoftBodyTwin::linkEnds(std::size_t link) const
{
    const btSoftBody::Link& l = m_body->m_links[int(link)];
    const btSoftBody::Node* first = &m_body->m_nodes[0];
    return {Index(l.m_n[0] - first), Index(l.m_n[1] - first)};
}

Real SoftBodyTwin::linkRestLength(std::size_t link) const
{
    return m_body->m_links[int(link)].m_rl;
}

Real SoftBodyTwin::linkStiffness(std::size_t link) const
{
    return m_body->m_links[int(link)].m_material->m_kLST;
}

std::size_t SoftBodyTwin::touchingCount() const
{
    std::size_t count = 0;
    for (int obstacle : m_touchObstacle)
    {
        count += obstacle >= 0 ? 1 : 0;
    }
    return count;
}

Real SoftBodyTwin::kineticEnergy() const
{
    Real energy = 0;
    for (int i = 0; i < m_body->m_nodes.size(); ++i)
    {
        const btSoftBody::Node& node = m_body->m_nodes[i];
        if (node.m_im > 0)
        {
            energy += Real(0.5) / node.m_im * node.m_v.length2();
        }
    }
    return energy;
}
} // namespace masse::bridge
