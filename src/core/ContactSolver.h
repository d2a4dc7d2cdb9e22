#pragma once
/// Keeps sheet masses out of obstacles and applies the contact response (sticky, Coulomb friction, frictionless).
///
/// Once per frame, the detector finds every obstacle a mass could reach within the frame and gives its supporting
/// plane (speculative contacts, as Box2D and Jolt use). After every integrator substep each mass is projected out of
/// its planes and its approach velocity removed: a few dot products per contact, so contact stays cheap however many
/// substeps an explicit integrator takes. At the end of the frame, any mass that moved farther than its reach is
/// checked by a swept test, so nothing tunnels through a thin obstacle.
///
/// Friction acts at the impulse level: the tangential velocity a contact may remove in one substep is mu times the
/// normal velocity it removed, which reproduces Coulomb's law (a block on a slope of angle a slides with acceleration
/// g (sin a - mu cos a), and stays when mu > tan a).

#include "Contact.h"
#include "MassSpringSystem.h"
#include "StageObserver.h"
#include "StepContext.h"

#include <utility>
#include <vector>

namespace masse
{
/// The first contact of the sheet with one obstacle.
struct ContactEvent
{
    int obstacle;
    Real time; ///< s, simulated, at the end of the substep that made the contact
};

class ContactSolver
{
public:
    ContactSolver(ContactDetector& detector, const ContactSettings& settings);

    void setSettings(const ContactSettings& settings);
    const ContactSettings& settings() const { return m_settings; }

    /// Called by the Simulator around the substeps of every frame. With `constrain`, the integrator honours velocity
    /// constraints, and stuck and resting masses are handed to it as such in context.constraints (see
    /// VelocityConstraint.h), whose reactions afterSubstep reads; endFrame clears them.
    void beginFrame(MassSpringSystem& system, StepContext& context, Real time, Real dt, bool constrain);
    void afterSubstep(MassSpringSystem& system, const StepContext& context, Real h);
    void endFrame(MassSpringSystem& system, StepContext& context, Real time);

    // Reports of the last frame.
    /// Obstacle each mass touched during the last frame, or -1.
    const std::vector<int>& touchingObstacle() const { return m_touchObstacle; }
    /// Face of that obstacle, or -1.
    const std::vector<int>& touchingFace() const { return m_touchFace; }
    /// Mean contact force on each mass over the last frame (N).
    const std::vector<Vec3>& contactForce() const { return m_contactForce; }
    /// Masses held by sticky contact.
    const std::vector<std::uint8_t>& stuck() const { return m_stuck; }
    /// (obstacle, face) pairs touched during the last frame, sorted, each once.
    const std::vector<std::pair<int, int>>& touchedFaces() const { return m_touchedFaces; }
    std::size_t touchingCount() const { return m_touchingCount; }
    std::size_t planeCount() const { return m_planes.size(); }

    // History of the run.
    /// First contact with each obstacle, in the order they happened.
    const std::vector<ContactEvent>& firstContacts() const { return m_firstContacts; }
    bool everTouched(int obstacle) const;

    /// Deepest penetration of any mass's sphere into an obstacle now (m, 0 if none), measured afresh by the detector.
    Real maxPenetration(const MassSpringSystem& system);
    /// Releases every stuck mass (for a reset or a change of response).
    void releaseAll();
    /// Told when each contact stage begins and ends (nullptr: nobody); a profiler outside the core reads its clock.
    void setStageObserver(StageObserver* observer) { m_observer = observer; }

private:
    /// Records that a mass touches an obstacle this frame (called for every active contact of every substep, so
    /// it stays inline and cheap: the first-contact event is the rare path).
    void touch(Index mass, int obstacle, int face)
    {
        if (m_touchObstacle[mass] < 0)
        {
            m_touchObstacle[mass] = obstacle;
            m_touchFace[mass] = face;
        }
        if (obstacle >= 0 && std::size_t(obstacle) < m_obstacleTouched.size() &&
            !m_obstacleTouched[std::size_t(obstacle)])
        {
            recordFirstContact(obstacle);
        }
    }
    /// touch() for the parallel projection: the first-contact check is only read, and an obstacle touched for the
    /// first time is noted in the chunk's list, merged in chunk order afterwards (so events do not depend on threads).
    void touchInChunk(Index mass, int obstacle, int face, std::vector<int>& firstTouches)
    {
        if (m_touchObstacle[mass] < 0)
        {
            m_touchObstacle[mass] = obstacle;
            m_touchFace[mass] = face;
        }
        if (obstacle >= 0 && std::size_t(obstacle) < m_obstacleTouched.size() &&
            !m_obstacleTouched[std::size_t(obstacle)])
        {
            firstTouches.push_back(obstacle);
        }
    }
    /// Projects mass i out of its planes after a substep of h (its part of afterSubstep; touches only mass i's state).
    void projectMass(Particles& p, Index i, Real h, std::vector<int>& firstTouches, bool& madeStuck);
    void recordFirstContact(int obstacle);
    /// Sorts the frame's planes by mass and fills m_planeOffsets.
    void indexPlanesByMass(std::size_t masses);
    void resizeFor(std::size_t masses);

    ContactDetector& m_detector;
    ContactSettings m_settings;

    std::vector<ContactPlane> m_planes; ///< sorted by mass (stably), so each mass's planes are contiguous
    std::vector<std::size_t> m_planeOffsets; ///< mass i's planes are m_planes[m_planeOffsets[i], m_planeOffsets[i + 1])
    std::vector<Vec3> m_frameStart;
    std::vector<Real> m_reach;
    std::vector<Vec3> m_impulse;
    // Resting contact handed to the implicit integrator this frame.
    std::vector<std::uint8_t> m_resting;
    std::vector<Vec3> m_restingNormal;
    std::vector<Vec3> m_restingVelocity;
    std::vector<Real> m_restingDamping;
    std::vector<int> m_restingObstacle;
    std::vector<int> m_restingFace;
    std::vector<std::size_t> m_restingConstraint; ///< index into StepContext::constraints
    std::vector<std::size_t> m_restingPlane;      ///< index into m_planes of the surface it rests on
    std::vector<Vec3> m_lastReaction;             ///< N s, from the previous frame's solve
    std::vector<std::uint8_t> m_wasResting;
    std::vector<Index> m_restingMasses;
    bool m_anyStuck = false;
    Real m_frameTime = 0;
    Real m_frameDt = 0;
    Real m_elapsed = 0;

    std::vector<std::uint8_t> m_stuck;
    std::vector<Vec3> m_anchor;
    std::vector<Vec3> m_stuckNormal;
    std::vector<Vec3> m_stuckVelocity;
    std::vector<int> m_stuckObstacle;
    std::vector<int> m_stuckFace;

    std::vector<int> m_touchObstacle;
    std::vector<int> m_touchFace;
    std::vector<Vec3> m_contactForce;
    std::vector<std::pair<int, int>> m_touchedFaces;
    std::size_t m_touchingCount = 0;
    std::vector<ContactEvent> m_firstContacts;
    StageObserver* m_observer = nullptr;
    std::vector<std::uint8_t> m_obstacleTouched;
};
} // namespace masse
