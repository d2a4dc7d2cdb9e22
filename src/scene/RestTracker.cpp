#include "scene/RestTracker.h"

namespace masse::scene
{
bool RestTracker::update(Real time, Real kineticEnergy, bool ready)
{
    if (!ready || kineticEnergy >= m_threshold)
    {
        m_since = -1;
        return false;
    }
    if (m_since < 0)
    {
        m_since = time;
    }
    if (m_rested || !atRest(time))
    {
        return false;
    }
    m_rested = true;
    return true;
}
} // namespace masse::scene
