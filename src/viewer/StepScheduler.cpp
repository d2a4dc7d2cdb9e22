#include "StepScheduler.h"

#include <algorithm>

namespace masse::viewer
{
StepScheduler::StepScheduler(Real dt, Real maxLag) : m_dt(dt), m_maxLag(maxLag) {}

void StepScheduler::setStep(Real dt)
{
    m_dt = dt;
    m_owed = std::min(m_owed, dt);
}

bool StepScheduler::addWallTime(Real seconds)
{
    m_owed += std::max(seconds, Real(0));
    // Never less than one step, or a step longer than the cap could never come due.
    const Real cap = std::max(m_maxLag, m_dt);
    if (m_owed <= cap)
    {
        return false;
    }
    m_owed = cap;
    return true;
}

void StepScheduler::stepTaken()
{
    m_owed = std::max(Real(0), m_owed - m_dt);
}

void RateMeter::add(Real wallSeconds, int frames, int steps, Real simSeconds, bool behind)
{
    m_wall += wallSeconds;
    m_frames += frames;
    m_behind = m_behind || behind;
    m_steps += steps;
    m_sim += simSeconds;
    if (m_wall < m_window)
    {
        return;
    }
    m_fps = Real(m_frames) / m_wall;
    m_sps = Real(m_steps) / m_wall;
    m_realTime = m_sim / m_wall;
    m_fellBehind = m_behind;
    m_published = true;
    m_behind = false;
    m_wall = 0;
    m_frames = 0;
    m_steps = 0;
    m_sim = 0;
}
} // namespace masse::viewer
