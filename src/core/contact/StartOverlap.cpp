#include "core/contact/StartOverlap.h"

#include <algorithm>

namespace masse
{
void StartOverlap::update(const Particles& p, const ContactPlanes& planes, Real radius)
{
    const bool first = !m_started;
    m_started = true;
    if (!first && !any)
    {
        return;
    }
    m_next.assign(p.size(), 0);
    bool found = false;
    // A mass on the surface is at -radius to rounding: a millionth of the radius more still counts as on it.
    const Real onSurface = radius + Real(1e-6) * radius;
    for (std::size_t j = 0; j < planes.massCount(); ++j)
    {
        const Index i = planes.mass(j);
        if (p.pinned[i] || (!first && !(depth[i] > 0)))
        {
            continue;
        }
        Real deepest = 0;
        for (std::size_t k = planes.firstPlane(j); k < planes.endPlane(j); ++k)
        {
            deepest = std::max(deepest, -planes[k].separation(p.position[i], radius));
        }
        if (first && deepest > onSurface)
        {
            continue;
        }
        deepest = std::min(deepest, radius);
        m_next[i] = first ? deepest : std::min(depth[i], deepest);
        found = found || m_next[i] > 0;
    }
    depth.swap(m_next);
    any = found;
}
} // namespace masse
