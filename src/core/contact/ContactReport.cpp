#include "core/contact/ContactReport.h"

#include "core/parallel/TaskPool.h"

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
    // Over chunks of masses on all threads. Each chunk lists its touched faces without the repeats of its
    // neighbours (a sheet on a table touches one face with thousands of masses in a row): sorting every touching mass's
    // pair would be most of this pass on a 256x2x256 sheet resting on two boxes. The sorted, unique list and the count
    // do not depend on how the masses are split.
    const Real inverseDt = dt > 0 ? Real(1) / dt : Real(0);
    const std::size_t masses = m_impulse.size();
    const std::size_t chunks = chunkCount(masses, massChunkSize);
    m_chunkFaces.reserveChunks(chunks);
    m_chunkTouching.assign(chunks, 0);
    parallelFor(masses, massChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    const std::size_t chunk = begin / massChunkSize;
                    std::vector<std::pair<int, int>>& faces = m_chunkFaces[chunk];
                    faces.clear();
                    std::size_t touching = 0;
                    for (std::size_t i = begin; i < end; ++i)
                    {
                        m_contactForce[i] = m_impulse[i] * inverseDt;
                        if (m_touchObstacle[i] >= 0)
                        {
                            ++touching;
                            const std::pair<int, int> face(m_touchObstacle[i], m_touchFace[i]);
                            if (faces.empty() || faces.back() != face)
                            {
                                faces.push_back(face);
                            }
                        }
                    }
                    m_chunkTouching[chunk] = touching;
                });
    m_touchingCount = 0;
    for (std::size_t chunk = 0; chunk < chunks; ++chunk)
    {
        m_touchingCount += m_chunkTouching[chunk];
        m_touchedFaces.insert(m_touchedFaces.end(), m_chunkFaces[chunk].begin(), m_chunkFaces[chunk].end());
    }
    std::sort(m_touchedFaces.begin(), m_touchedFaces.end());
    m_touchedFaces.erase(std::unique(m_touchedFaces.begin(), m_touchedFaces.end()), m_touchedFaces.end());
}
} // namespace masse
