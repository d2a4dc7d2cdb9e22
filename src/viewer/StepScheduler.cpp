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

} // namespace masse::viewer
