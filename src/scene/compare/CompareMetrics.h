#pragma once
/// Measures for setting two simulations of one sheet side by side (MaSSE and its Bullet twin): how far apart
/// corresponding masses are, how deep mass spheres sink into obstacles, how many masses went into or through an
/// obstacle, how kinetic energy evolves, and what each run cost in wall time.
///
/// Free of Bullet on purpose: obstacles reach it only as numbers (signed distances) and one segment test
/// (ObstacleQuery), so both engines' positions are measured by the same function (ObstacleProbe.h makes it from the
/// core's ContactDetector) and tests can feed made-up trajectories and analytic shapes.

#include "core/Types.h"

#include <functional>
#include <vector>

namespace masse::scene
{
/// Distance between corresponding masses of two position arrays.
struct PositionDistance
{
    Real rms = 0;   ///< m, sqrt of the mean of |a_i - b_i|^2
    Real max = 0;   ///< m
    Index mass = 0; ///< where the largest distance is
};

/// Throws std::invalid_argument if the arrays differ in size or are empty (a caller's bug, not bad input).
PositionDistance positionDistance(const std::vector<Vec3>& a, const std::vector<Vec3>& b);

/// Penetration of mass spheres of one radius into obstacles over a run, from the signed distance d of each centre to
/// the nearest obstacle surface (negative inside a solid): a sphere's depth is max(0, radius - d).
class PenetrationStats
{
public:
    explicit PenetrationStats(Real radius);

    /// One frame: the signed distance (m) of every mass. Throws std::invalid_argument on a NaN.
    void addFrame(const std::vector<Real>& signedDistances);

    Real radius() const { return m_radius; }
    /// m, deepest of any mass in any frame.
    Real max() const { return m_max; }
    /// m, mean depth over every mass in every frame, masses clear of obstacles counting 0.
    Real mean() const { return m_samples ? m_sum / Real(m_samples) : 0; }
    /// m, mean depth over the samples that penetrate (0 if none did).
    Real meanWhenPenetrating() const { return m_penetrating ? m_sum / Real(m_penetrating) : 0; }
    /// m, deepest in the last frame.
    Real lastFrameMax() const { return m_lastMax; }
    std::size_t frames() const { return m_frames; }
    std::size_t samples() const { return m_samples; }
    std::size_t penetratingSamples() const { return m_penetrating; }

private:
    Real m_radius;
    Real m_max = 0;
    Real m_sum = 0;
    Real m_lastMax = 0;
    std::size_t m_frames = 0;
    std::size_t m_samples = 0;
    std::size_t m_penetrating = 0;
};

/// The one geometric question tunnel counting asks of the obstacles.
struct ObstacleQuery
{
    /// Whether the straight segment from `from` to `to` meets the surface of an obstacle.
    std::function<bool(const Vec3& from, const Vec3& to)> segmentHits;
};

/// How many masses went into or through an obstacle.
struct TunnelCount
{
    std::size_t inside = 0;        ///< centre inside a solid obstacle at the last frame
    std::size_t beyond = 0;        ///< centre outside, but on the far side of an obstacle it went through
    std::size_t entered = 0;       ///< centre entered an obstacle at some frame (includes the two above)
    std::size_t startedInside = 0; ///< inside at the start: not judged
    std::size_t tunnelled() const { return inside + beyond; }
};

/// Counts masses that tunnelled, robustly to masses that slide round an obstacle or touch it.
///
/// A mass's centre, not its sphere, is what must not cross a surface: a resting sphere overlaps by less than its
/// radius, so its centre stays outside. Between two frames the centre is taken to move along the straight segment
/// joining its positions (all either engine defines). A mass has *entered* an obstacle at the first frame where its
/// centre is inside a solid (signed distance < 0) or its segment from the previous frame meets an obstacle's
/// surface; `entryFrom` is its position at the frame before. At the end, a mass has *tunnelled* when its centre is
/// inside a solid, or when it entered and the segment from `entryFrom` to its final position still meets an
/// obstacle: it ended on the other side of what it went into. A mass that dipped in and came back out the same side,
/// or that went round an edge without its centre ever entering, is not counted. Masses that start inside are left
/// out (startedInside).
///
/// With a mesh obstacle, whose distance from BulletEnvironment::nearestSurface is unsigned, only the segment tests
/// see tunnelling.
class TunnelCounter
{
public:
    /// Starts from the masses' initial positions and signed distances.
    TunnelCounter(const std::vector<Vec3>& start, const std::vector<Real>& startDistances, ObstacleQuery query);

    /// One frame: every mass's position and the signed distance of its centre.
    void addFrame(const std::vector<Vec3>& positions, const std::vector<Real>& signedDistances);

    /// The count at the last frame added.
    TunnelCount count() const;
    /// Whether mass i has entered an obstacle so far.
    bool entered(Index i) const { return m_entered[i] != 0; }

private:
    ObstacleQuery m_query;
    std::vector<Vec3> m_last;
    std::vector<Real> m_lastDistance;
    std::vector<Vec3> m_entryFrom;
    std::vector<std::uint8_t> m_entered;
    std::vector<std::uint8_t> m_startedInside;
};

/// One engine's run, frame by frame, and what it cost.
struct RunRecord
{
    Real startTime = 0;              ///< s, simulated, when the run began
    std::vector<Real> time;          ///< s, simulated, at the end of each frame
    std::vector<Real> kineticEnergy; ///< J, at the end of each frame
    double wallSeconds = 0;          ///< spent stepping the engine (measurements excluded)

    void addFrame(Real t, Real energy, double stepWallSeconds);
    Real simulatedSeconds() const { return time.empty() ? 0 : time.back() - startTime; }
    /// Wall milliseconds per simulated second; 0 before the first frame.
    Real wallMsPerSimulatedSecond() const;
};
} // namespace masse::scene
