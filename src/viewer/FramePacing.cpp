#include "FramePacing.h"

namespace masse::viewer
{
bool frameDue(const FrameMoment& moment, const FramePacing& pacing)
{
    if (moment.mustDraw)
    {
        return true;
    }
    const Real interval = moment.paused       ? pacing.pausedInterval
                          : moment.newPicture ? pacing.runningInterval
                                              : pacing.idleInterval;
    return moment.sinceLastFrame >= interval;
}
} // namespace masse::viewer
