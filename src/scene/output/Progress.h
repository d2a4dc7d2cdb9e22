#pragma once
/// Progress of a run on the terminal: one line redrawn in place on a terminal, plain lines every few seconds when
/// the output is a file or a pipe (CI logs stay readable).

#include "core/Types.h"

#include <chrono>
#include <ostream>
#include <string>

namespace masse::scene
{
class Progress
{
public:
    Progress(std::ostream& out, bool terminal, Real duration);
    /// Shows simulated time, real-time factor and the latest event, at most 10 times a second (every 5 s of wall
    /// time when not on a terminal).
    void update(Real simTime, Real wallSeconds, const std::string& latestEvent);
    void finish(Real simTime, Real wallSeconds);

private:
    std::string line(Real simTime, Real wallSeconds, const std::string& latestEvent) const;

    std::ostream& m_out;
    bool m_terminal;
    Real m_duration;
    Real m_lastShown = -1;
};
} // namespace masse::scene
