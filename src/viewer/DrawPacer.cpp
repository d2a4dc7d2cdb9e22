#include "DrawPacer.h"

#include <algorithm>

namespace masse::viewer
{
namespace
{
/// Follows a rising cost slowly, so one slow frame or step (a scene rebuilt, a screenshot) does not stall the
/// next ones; a falling cost is taken at once.
Real smoothed(Real previous, Real latest)
{
    return std::min(latest, Real(0.8) * previous + Real(0.2) * latest);
}
} // namespace

void DrawPacer::stepped(int steps, Real seconds, Real dt)
{
    if (steps > 0 && dt > 0)
    {
        m_load = smoothed(m_load, seconds / (Real(steps) * dt));
    }
}

void DrawPacer::drew(Real start, Real cost)
{
    m_drawCost = smoothed(m_drawCost, cost);
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
