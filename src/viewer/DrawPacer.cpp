#include "DrawPacer.h"

#include <algorithm>

namespace masse::viewer
{
namespace
{
/// A moving average over the last few samples: a frame's cost wanders (llvmpipe, other processes), and pacing by a
/// low or high outlier would give drawing more or less than its share.
Real averaged(Real previous, Real latest, bool first)
{
    return first ? latest : Real(0.8) * previous + Real(0.2) * latest;
}
} // namespace

void DrawPacer::stepped(int steps, Real seconds, Real dt)
{
    if (steps > 0 && dt > 0)
    {
        m_load = averaged(m_load, seconds / (Real(steps) * dt), !m_stepped);
        m_stepped = true;
    }
}

void DrawPacer::drew(Real start, Real cost)
{
    m_drawCost = averaged(m_drawCost, cost, !m_drawn);
    m_drawn = true;
    m_lastStart = start;
}

Real DrawPacer::drawShare() const
{
    return std::clamp(1 - m_load - m_pacing.margin, m_pacing.minShare, m_pacing.maxShare);
}

Real DrawPacer::interval(bool simulationRunning) const
{
    if (!simulationRunning)
    {
        return m_pacing.minInterval;
    }
    return std::max(m_pacing.minInterval, m_drawCost / drawShare());
}
} // namespace masse::viewer
