#include "StepScheduler.h"

#include <algorithm>
#include <cmath>

namespace masse::viewer
{
StepScheduler::StepScheduler(Real dt, Real maxFrameSeconds) : m_dt(dt), m_maxFrameSeconds(maxFrameSeconds) {}

void StepScheduler::setStep(Real dt)
{
    m_dt = dt;
    m_owed = std::min(m_owed, dt);
}

void StepScheduler::addWallTime(Real seconds)
{
    m_owed += std::clamp(seconds, Real(0), m_maxFrameSeconds);
}

void StepScheduler::stepTaken()
{
    m_owed = std::max(Real(0), m_owed - m_dt);
}

void StepScheduler::forgetBacklog()
{
    // Keep the fraction of a step already banked, so the next frame's step comes on time.
    m_owed = std::fmod(m_owed, m_dt);
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
