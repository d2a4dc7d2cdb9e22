#include "scene/compare/CompareMetrics.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace masse::scene
{
PositionDistance positionDistance(const std::vector<Vec3>& a, const std::vector<Vec3>& b)
{
    if (a.size() != b.size() || a.empty())
    {
        throw std::invalid_argument("positionDistance: arrays of " + std::to_string(a.size()) + " and " +
                                    std::to_string(b.size()) + " positions");
    }
    PositionDistance result;
    Real sumSquares = 0;
    for (std::size_t i = 0; i < a.size(); ++i)
    {
        const Real squared = (a[i] - b[i]).squaredNorm();
        sumSquares += squared;
        const Real distance = std::sqrt(squared);
        if (distance > result.max)
        {
            result.max = distance;
            result.mass = Index(i);
        }
    }
    result.rms = std::sqrt(sumSquares / Real(a.size()));
    return result;
}

PenetrationStats::PenetrationStats(Real radius) : m_radius(radius)
{
    if (!(radius >= 0) || !std::isfinite(radius))
    {
        throw std::invalid_argument("PenetrationStats: radius must be finite and >= 0");
    }
}

void PenetrationStats::addFrame(const std::vector<Real>& signedDistances)
{
    Real frameMax = 0;
    for (Real d : signedDistances)
    {
        if (std::isnan(d))
        {
            throw std::invalid_argument("PenetrationStats: a signed distance is NaN");
        }
        const Real depth = std::max(Real(0), m_radius - d);
        if (depth > 0)
        {
            m_sum += depth;
            ++m_penetrating;
        }
        frameMax = std::max(frameMax, depth);
    }
    m_samples += signedDistances.size();
    m_max = std::max(m_max, frameMax);
    m_lastMax = frameMax;
    ++m_frames;
}

TunnelCounter::TunnelCounter(const std::vector<Vec3>& start, const std::vector<Real>& startDistances,
                             ObstacleQuery query)
    : m_query(std::move(query)), m_last(start), m_lastDistance(startDistances), m_entryFrom(start),
      m_entered(start.size(), 0), m_startedInside(start.size(), 0)
{
    if (start.size() != startDistances.size())
    {
        throw std::invalid_argument("TunnelCounter: positions and distances differ in count");
    }
    for (std::size_t i = 0; i < start.size(); ++i)
    {
        m_startedInside[i] = startDistances[i] < 0 ? 1 : 0;
    }
}

void TunnelCounter::addFrame(const std::vector<Vec3>& positions, const std::vector<Real>& signedDistances)
{
    if (positions.size() != m_last.size() || signedDistances.size() != m_last.size())
    {
        throw std::invalid_argument("TunnelCounter: a frame with a different number of masses");
    }
    for (std::size_t i = 0; i < positions.size(); ++i)
    {
        if (!m_entered[i] && !m_startedInside[i] &&
            (signedDistances[i] < 0 || m_query.segmentHits(m_last[i], positions[i])))
        {
            m_entered[i] = 1;
            m_entryFrom[i] = m_last[i];
        }
        m_last[i] = positions[i];
        m_lastDistance[i] = signedDistances[i];
    }
}

TunnelCount TunnelCounter::count() const
{
    TunnelCount result;
    for (std::size_t i = 0; i < m_last.size(); ++i)
    {
        if (m_startedInside[i])
        {
            ++result.startedInside;
            continue;
        }
        if (!m_entered[i])
        {
            continue;
        }
        ++result.entered;
        if (m_lastDistance[i] < 0)
        {
            ++result.inside;
        }
        else if (m_query.segmentHits(m_entryFrom[i], m_last[i]))
        {
            ++result.beyond;
        }
    }
    return result;
}

void RunRecord::addFrame(Real t, Real energy, double stepWallSeconds)
{
    time.push_back(t);
    kineticEnergy.push_back(energy);
    wallSeconds += stepWallSeconds;
}

Real RunRecord::wallMsPerSimulatedSecond() const
{
    const Real simulated = simulatedSeconds();
    return simulated > 0 ? Real(1000) * Real(wallSeconds) / simulated : Real(0);
}
} // namespace masse::scene
