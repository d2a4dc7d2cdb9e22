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
    /// Shows simulated time, real-time factor, the time left at the pace so far (ETA) and the latest event, at most
    /// 10 times a second (every 5 s of wall time when not on a terminal).
    void update(Real simTime, Real wallSeconds, const std::string& latestEvent);
    /// The last line. A run that ended before its duration because the sheet came to rest says so ("stopped at rest
    /// at t = 3.21 s of 10.00 s") with a full bar: a bar at 32% would read as an abort.
    void finish(Real simTime, Real wallSeconds, bool stoppedAtRest = false);

    /// The line shown for a run at `simTime` after `wallSeconds` (the ETA while it runs, "done" or "stopped at rest"
    /// when `finished`).
    std::string line(Real simTime, Real wallSeconds, const std::string& latestEvent, bool finished = false,
                     bool stoppedAtRest = false) const;

private:
    std::ostream& m_out;
    bool m_terminal;
    Real m_duration;
    Real m_lastShown = -1;
};
} // namespace masse::scene
