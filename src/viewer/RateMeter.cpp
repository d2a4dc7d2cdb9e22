#include "RateMeter.h"

namespace masse::viewer
{
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
