#include "ContactReport.h"

#include <algorithm>

namespace masse
{
void ContactReport::beginFrame(std::size_t masses, std::size_t obstacles)
{
    if (m_touchObstacle.size() != masses)
    {
        m_touchObstacle.assign(masses, -1);
        m_touchFace.assign(masses, -1);
        m_impulse.assign(masses, Vec3::Zero());
        m_contactForce.assign(masses, Vec3::Zero());
    }
    m_obstacleTouched.resize(obstacles, 0);
    m_touchedFaces.clear();
}

void ContactReport::recordFirstContact(int obstacle, Real time)
{
    m_obstacleTouched[std::size_t(obstacle)] = 1;
    m_firstContacts.push_back({obstacle, time});
}

void ContactReport::recordFirstTouches(const std::vector<int>& obstacles, Real time)
{
    for (const int obstacle : obstacles)
    {
        if (!m_obstacleTouched[std::size_t(obstacle)])
        {
            recordFirstContact(obstacle, time);
        }
    }
}

void ContactReport::endFrame(Real dt)
{
    m_touchingCount = 0;
    const Real inverseDt = dt > 0 ? Real(1) / dt : Real(0);
    for (std::size_t i = 0; i < m_impulse.size(); ++i)
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
} // namespace masse
