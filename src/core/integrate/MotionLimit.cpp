#include "core/integrate/MotionLimit.h"

#include "core/parallel/TaskPool.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace masse
{
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
        // Nothing tells yet how fast the loads will move the sheet: the first frame is taken in the most solves.
        // A sheet at rest under a load that rises over the frame (the vacuum cup's) has no speed to predict from;
        // in one solve of the whole frame the 64x2x64 cup's sheet moves 1.4 cm (3.4 spacings), and the run then
        // diverges at t = 0.03 s (`--set integrator.max_motion=0`).
        m_velocityBefore = velocity;
        m_predictedMotion = std::numeric_limits<Real>::infinity();
        return m_maxSolves;
    }
    // Each chunk's largest speed bound, then the largest of those: a maximum does not depend on the split.
    std::vector<Real>& chunkLargest = m_chunkLargest;
    chunkLargest.assign(chunkCount(n, massChunkSize), 0);
    parallelFor(n, massChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    Real largest = 0;
                    for (std::size_t i = begin; i < end; ++i)
                    {
                        const Real speed = velocity[i].norm() + (velocity[i] - m_velocityBefore[i]).norm();
                        largest = std::max(largest, speed);
                    }
                    chunkLargest[begin / massChunkSize] = largest;
                });
    const Real speed = chunkLargest.empty() ? Real(0) : *std::max_element(chunkLargest.begin(), chunkLargest.end());
    m_velocityBefore = velocity;
    m_predictedMotion = speed * dt;
    if (!std::isfinite(m_predictedMotion))
    {
        return m_maxSolves; // the guard names the mass; the split must not overflow first
    }
    const Real solves = std::ceil(m_predictedMotion / m_maxMotion);
    return solves > 1 ? int(std::min(solves, Real(m_maxSolves))) : 1;
}
} // namespace masse
