#include "ContactPlanes.h"

#include <algorithm>

namespace masse
{
void ContactPlanes::index(std::size_t masses)
{
    // The Bullet detector appends planes in mass order already; a test detector need not, so sort stably (each
    // mass's planes keep their order, which is the order they are applied in).
    const auto byMass = [](const ContactPlane& x, const ContactPlane& y) { return x.mass < y.mass; };
    if (!std::is_sorted(m_planes.begin(), m_planes.end(), byMass))
    {
        std::stable_sort(m_planes.begin(), m_planes.end(), byMass);
    }
    m_offsets.assign(masses + 1, 0);
    for (const ContactPlane& plane : m_planes)
    {
        ++m_offsets[std::size_t(plane.mass) + 1];
    }
    for (std::size_t i = 0; i < masses; ++i)
    {
        m_offsets[i + 1] += m_offsets[i];
    }
}
} // namespace masse
