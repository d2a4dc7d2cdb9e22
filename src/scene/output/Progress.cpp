#include "scene/output/Progress.h"

#include <algorithm>
#include <cstdio>

namespace masse::scene
{
Progress::Progress(std::ostream& out, bool terminal, Real duration)
    : m_out(out), m_terminal(terminal), m_duration(duration)
{
}

namespace
{
/// A wall-clock span for the ETA: "45 s", "3 min 05 s", "2 h 07 min".
std::string span(Real seconds)
{
    const long long s = (long long)(seconds + 0.5);
    char text[48];
    if (s < 60)
    {
        std::snprintf(text, sizeof(text), "%lld s", s);
    }
    else if (s < 3600)
    {
        std::snprintf(text, sizeof(text), "%lld min %02lld s", s / 60, s % 60);
    }
    else
    {
        std::snprintf(text, sizeof(text), "%lld h %02lld min", s / 3600, (s % 3600) / 60);
    }
    return text;
}
} // namespace

std::string Progress::line(Real simTime, Real wallSeconds, const std::string& latestEvent, bool finished,
                           bool stoppedAtRest) const
{
    const bool atRest = finished && stoppedAtRest && simTime < m_duration;
    const Real fraction = atRest || m_duration <= 0 ? Real(1) : std::clamp(simTime / m_duration, Real(0), Real(1));
    constexpr int width = 24;
    const int filled = int(fraction * width + 0.5);
    const std::string bar = std::string(std::size_t(filled), '#') + std::string(std::size_t(width - filled), '.');
    const double factor = wallSeconds > 0 ? simTime / wallSeconds : 0.0;
    char text[240];
    if (atRest)
    {
        std::snprintf(text, sizeof(text), "[%s] stopped at rest at t = %.2f s of %.2f s  %6.2fx real time", bar.c_str(),
                      simTime, m_duration, factor);
    }
    else
    {
        std::snprintf(text, sizeof(text), "[%s] %5.1f%%  t = %7.2f / %.2f s  %6.2fx real time", bar.c_str(),
                      100 * fraction, simTime, m_duration, factor);
    }
    std::string result = text;
    if (finished)
    {
        result += "  done in " + span(wallSeconds);
    }
    else if (simTime > 0 && wallSeconds > 0 && simTime < m_duration)
    {
        // At the pace so far: a run that stops at rest ends sooner.
        result += "  ETA " + span(wallSeconds * (m_duration - simTime) / simTime);
    }
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

void Progress::finish(Real simTime, Real wallSeconds, bool stoppedAtRest)
{
    const std::string last = line(simTime, wallSeconds, "", true, stoppedAtRest);
    if (m_terminal)
    {
        m_out << '\r' << last << "\033[K\n" << std::flush;
    }
    else
    {
        m_out << last << '\n' << std::flush;
    }
}
} // namespace masse::scene
