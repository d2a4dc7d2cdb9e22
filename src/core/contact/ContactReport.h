#pragma once
/// What the sheet's contact did: in the last frame (which obstacle and face each mass touched, the contact force on
/// each mass, the faces touched), and over the run (the first contact with each obstacle). The contact stages write
/// it; the scene, the viewer and the reports read it between frames. It changes no mass's state.

#include "core/Types.h"
#include "core/parallel/PerChunk.h"

#include <cstdint>
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

class ContactReport
{
public:
    /// Sizes the per-mass arrays for `masses` and the history for `obstacles` (keeping what it already holds).
    void beginFrame(std::size_t masses, std::size_t obstacles);
    /// Clears mass i's touch and impulse for a new frame (called inside the solver's parallel pass over the masses).
    void clearMass(std::size_t i)
    {
        m_touchObstacle[i] = -1;
        m_touchFace[i] = -1;
        m_impulse[i] = Vec3::Zero();
    }
    /// Records that a mass touches an obstacle at `time` (serial stages). Called for every active contact of every
    /// substep, so it stays inline and cheap: the first-contact event is the rare path.
    void touch(Index mass, int obstacle, int face, Real time)
    {
        noteTouch(mass, obstacle, face);
        if (isFirstTouch(obstacle))
        {
            recordFirstContact(obstacle, time);
        }
    }
    /// touch() for a parallel stage: the history is only read, and an obstacle touched for the first time is noted in
    /// the chunk's list, recorded later in chunk order by recordFirstTouches (so events do not depend on threads).
    void touchInChunk(Index mass, int obstacle, int face, std::vector<int>& firstTouches)
    {
        noteTouch(mass, obstacle, face);
        if (isFirstTouch(obstacle))
        {
            firstTouches.push_back(obstacle);
        }
    }
    /// Whether touching `obstacle` now would be the sheet's first contact with it (what touch() records).
    bool isFirstTouch(int obstacle) const
    {
        return obstacle >= 0 && std::size_t(obstacle) < m_obstacleTouched.size() &&
               !m_obstacleTouched[std::size_t(obstacle)];
    }
    /// Records a chunk's first touches at `time`, skipping obstacles an earlier chunk already recorded.
    void recordFirstTouches(const std::vector<int>& obstacles, Real time);
    /// The impulse (N s) contact gave mass i this frame.
    void addImpulse(std::size_t i, const Vec3& impulse) { m_impulse[i] += impulse; }
    /// The per-mass records of this frame as arrays (touched obstacle and face, impulse x y z per mass), for a kernel
    /// that records eight masses of its own range at once; what it writes must be what touch and addImpulse would.
    int* touchingObstacleData() { return m_touchObstacle.data(); }
    int* touchingFaceData() { return m_touchFace.data(); }
    Real* impulseData() { return m_impulse.data()->data(); }
    /// Turns the frame's impulses into mean forces over `dt` and lists the touched faces.
    void endFrame(Real dt);

    // The last frame.
    /// Obstacle each mass touched during the last frame, or -1.
    const std::vector<int>& touchingObstacle() const { return m_touchObstacle; }
    /// Face of that obstacle, or -1.
    const std::vector<int>& touchingFace() const { return m_touchFace; }
    /// Mean contact force on each mass over the last frame (N).
    const std::vector<Vec3>& contactForce() const { return m_contactForce; }
    /// (obstacle, face) pairs touched during the last frame, sorted, each once.
    const std::vector<std::pair<int, int>>& touchedFaces() const { return m_touchedFaces; }
    std::size_t touchingCount() const { return m_touchingCount; }

    // The run.
    /// First contact with each obstacle, in the order they happened.
    const std::vector<ContactEvent>& firstContacts() const { return m_firstContacts; }
    bool everTouched(int obstacle) const
    {
        return obstacle >= 0 && std::size_t(obstacle) < m_obstacleTouched.size() &&
               m_obstacleTouched[std::size_t(obstacle)];
    }

private:
    void noteTouch(Index mass, int obstacle, int face)
    {
        if (m_touchObstacle[mass] < 0)
        {
            m_touchObstacle[mass] = obstacle;
            m_touchFace[mass] = face;
        }
    }
    void recordFirstContact(int obstacle, Real time);

    std::vector<int> m_touchObstacle;
    std::vector<int> m_touchFace;
    std::vector<Vec3> m_impulse; ///< N s, this frame
    std::vector<Vec3> m_contactForce;
    std::vector<std::pair<int, int>> m_touchedFaces;
    std::size_t m_touchingCount = 0;
    std::vector<ContactEvent> m_firstContacts;
    std::vector<std::uint8_t> m_obstacleTouched;
    PerChunk<std::vector<std::pair<int, int>>> m_chunkFaces; ///< endFrame's per mass chunk faces, kept frame to frame
    std::vector<std::size_t> m_chunkTouching;                ///< endFrame's per mass chunk touching masses
};
} // namespace masse
