#include "core/integrate/MotionLimit.h"

#include "core/parallel/TaskPool.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace masse
{
namespace
{
/// The largest of measure(i) over the n masses: each chunk's largest (into `chunkLargest`, kept between calls), then
/// the largest of those. A maximum does not depend on the split, so neither does the result on the threads.
template <class Measure> Real largestOverMasses(std::size_t n, std::vector<Real>& chunkLargest, const Measure& measure)
{
    chunkLargest.assign(chunkCount(n, massChunkSize), 0);
    parallelFor(n, massChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    Real largest = 0;
                    for (std::size_t i = begin; i < end; ++i)
                    {
                        largest = std::max(largest, measure(i));
                    }
                    chunkLargest[begin / massChunkSize] = largest;
                });
    return chunkLargest.empty() ? Real(0) : *std::max_element(chunkLargest.begin(), chunkLargest.end());
}
} // namespace

MotionLimit::MotionLimit(Real maxMotion, int maxSolves) : m_maxMotion(maxMotion), m_maxSolves(maxSolves)
{
    if (!(maxMotion > 0) || !std::isfinite(maxMotion) || maxSolves < 1)
    {
        throw std::invalid_argument("MotionLimit: the motion must be a positive length and the solves at least 1");
    }
}

int MotionLimit::solvesFor(MassSpringSystem& system, Real dt)
{
    const std::vector<Vec3>& velocity = system.particles.velocity;
    const std::size_t n = velocity.size();
    const bool hasBefore = m_velocityBefore.size() == n;
    if (!hasBefore)
    {
        // Nothing tells yet how fast the loads will move the sheet: the first frame starts at the most solves, and
        // solvesForRest corrects the rest after each.
        // A sheet at rest under a load that rises over the frame (the vacuum cup's) has no speed to predict from;
        // in one solve of the whole frame the 64x2x64 cup's sheet moves 1.4 cm (3.4 spacings), and the run then
        // diverges at t = 0.03 s (`--set integrator.max_motion=0`).
        m_velocityBefore = velocity;
        m_predictedMotion = std::numeric_limits<Real>::infinity();
        m_guessing = true;
        m_velocityBySolve = velocity;
        m_frameSoFar = 0;
        m_solvesSoFar = 0;
        return m_maxSolves;
    }
    m_guessing = false;
    const Real speed = largestOverMasses(n, m_chunkLargest,
                                         [&](std::size_t i)
                                         { return velocity[i].norm() + (velocity[i] - m_velocityBefore[i]).norm(); });
    m_velocityBefore = velocity;
    m_predictedMotion = speed * dt;
    if (!std::isfinite(m_predictedMotion))
    {
        return m_maxSolves; // the guard names the mass; the split must not overflow first
    }
    const Real solves = std::ceil(m_predictedMotion / m_maxMotion);
    return solves > 1 ? int(std::min(solves, Real(m_maxSolves))) : 1;
}

int MotionLimit::solvesForRest(MassSpringSystem& system, Real taken, Real rest)
{
    if (!m_guessing)
    {
        return 0;
    }
    const std::vector<Vec3>& velocity = system.particles.velocity;
    const std::size_t n = velocity.size();
    m_frameSoFar += taken;
    ++m_solvesSoFar;
    // The largest speed, and the largest velocity change over the solve just taken.
    const Real speed = largestOverMasses(n, m_chunkLargest, [&](std::size_t i) { return velocity[i].norm(); });
    const Real change = largestOverMasses(n, m_chunkLargest,
                                          [&](std::size_t i) { return (velocity[i] - m_velocityBySolve[i]).norm(); });
    m_velocityBySolve = velocity;
    // The longest next solve L that keeps (speed + rate L) L within the limit, the velocity changing at the rate it
    // changed over the solve just taken: the positive root of rate L^2 + speed L - maxMotion.
    const Real rate = change / taken;
    Real longest = std::numeric_limits<Real>::infinity();
    if (rate > 0)
    {
        longest = 2 * m_maxMotion / (speed + std::sqrt(speed * speed + 4 * rate * m_maxMotion));
    }
    else if (speed > 0)
    {
        longest = m_maxMotion / speed;
    }
    longest = std::min(longest, 2 * m_frameSoFar);
    if (!std::isfinite(speed) || !std::isfinite(change) || !(longest > 0))
    {
        m_guessing = false;
        return 0; // the guard names the mass; keep the split as it was
    }
    const int most = std::max(1, m_maxSolves - m_solvesSoFar);
    const Real wanted = std::ceil(rest / longest);
    const int solves = wanted > 1 ? int(std::min(wanted, Real(most))) : 1;
    if (solves == 1)
    {
        m_guessing = false; // the frame ends with the next solve
    }
    return solves;
}
} // namespace masse
