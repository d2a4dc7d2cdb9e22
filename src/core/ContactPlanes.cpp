#include "ContactPlanes.h"

#include <algorithm>
#include <cstring>

namespace masse
{
namespace
{
/// Whether every bit of v is zero (+0 in each coordinate; -0 is not).
bool allBitsZero(const Vec3& v)
{
    static constexpr Real zeros[3] = {0, 0, 0};
    return std::memcmp(v.data(), zeros, sizeof(zeros)) == 0;
}
} // namespace

void ContactPlanes::index()
{
    // The Bullet detector appends planes in mass order already; a test detector need not, so sort stably (each
    // mass's planes keep their order, which is the order they are applied in).
    const auto byMass = [](const ContactPlane& x, const ContactPlane& y) { return x.mass < y.mass; };
    if (!std::is_sorted(m_planes.begin(), m_planes.end(), byMass))
    {
        std::stable_sort(m_planes.begin(), m_planes.end(), byMass);
    }
    const std::size_t count = m_planes.size();
    m_normalX.resize(count);
    m_normalY.resize(count);
    m_normalZ.resize(count);
    m_offset.resize(count);
    m_obstacle.resize(count);
    m_face.resize(count);
    m_entries.clear();
    m_stillRuns.clear();
    bool still = true;
    for (std::size_t k = 0; k < m_planes.size(); ++k)
    {
        const ContactPlane& plane = m_planes[k];
        m_normalX[k] = plane.normal.x();
        m_normalY[k] = plane.normal.y();
        m_normalZ[k] = plane.normal.z();
        m_offset[k] = plane.offset;
        m_obstacle[k] = plane.obstacle;
        m_face[k] = plane.face;
        if (m_entries.empty() || m_entries.back().mass != plane.mass)
        {
            if (!m_entries.empty() && m_entries.size() % runLength == 0)
            {
                m_stillRuns.push_back(still ? 1 : 0);
                still = true;
            }
            m_entries.push_back({plane.mass, std::uint32_t(k)});
        }
        still = still && allBitsZero(plane.velocity);
    }
    if (!m_entries.empty())
    {
        m_stillRuns.push_back(still ? 1 : 0);
    }
    m_entries.push_back({0, std::uint32_t(m_planes.size())});
}
} // namespace masse
