#include "scene/output/Progress.h"

#include <algorithm>
#include <cstdio>

namespace masse::scene
{
Progress::Progress(std::ostream& out, bool terminal, Real duration)
    : m_out(out), m_terminal(terminal), m_duration(duration)
{
}

std::string Progress::line(Real simTime, Real wallSeconds, const std::string& latestEvent) const
{
    const Real fraction = m_duration > 0 ? std::clamp(simTime / m_duration, Real(0), Real(1)) : Real(1);
    constexpr int width = 24;
    const int filled = int(fraction * width + 0.5);
    const std::string bar = std::string(std::size_t(filled), '#') + std::string(std::size_t(width - filled), '.');
    char text[200];
    std::snprintf(text, sizeof(text), "[%s] %5.1f%%  t = %7.2f / %.2f s  %6.2fx real time", bar.c_str(), 100 * fraction,
                  simTime, m_duration, wallSeconds > 0 ? simTime / wallSeconds : 0.0);
    std::string result = text;
    if (!latestEvent.empty())
    {
        result += "  last: " + latestEvent;
    }
    return result;
}

void Progress::update(Real simTime, Real wallSeconds, const std::string& latestEvent)
{
    const Real interval = m_terminal ? 0.1 : 5.0;
    if (m_lastShown >= 0 && wallSeconds - m_lastShown < interval)
    {
        return;
    }
    m_lastShown = wallSeconds;
    if (m_terminal)
    {
        m_out << '\r' << line(simTime, wallSeconds, latestEvent) << "\033[K" << std::flush;
    }
    else
    {
        m_out << line(simTime, wallSeconds, latestEvent) << '\n' << std::flush;
    }
}

void Progress::finish(Real simTime, Real wallSeconds)
{
    if (m_terminal)
    {
        m_out << '\r' << line(simTime, wallSeconds, "") << "\033[K\n" << std::flush;
    }
    else
    {
        m_out << line(simTime, wallSeconds, "") << '\n' << std::flush;
    }
}
} // namespace masse::scene
