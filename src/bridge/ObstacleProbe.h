#pragma once
/// The obstacles of a BulletEnvironment as CompareMetrics sees them: signed distances of mass centres and a segment
/// test, at the obstacles' current poses (call setTime first for kinematic ones). Measuring MaSSE's masses and the
/// twin's nodes with these same functions is what makes their penetration and tunnel figures comparable.

#include "CompareMetrics.h"

namespace masse::bridge
{
class BulletEnvironment;

/// Signed distance (m) of each point to the nearest obstacle surface, negative inside a solid (convex) obstacle.
/// Distances of `searchDistance` or more are reported as `searchDistance`: only the near ones matter to penetration.
std::vector<Real> signedDistances(BulletEnvironment& environment, const std::vector<Vec3>& points, Real searchDistance);

/// Segment test for TunnelCounter: a sweep of a 1 micrometre sphere (Bullet's convex sweep needs a volume) from one
/// end to the other.
ObstacleQuery obstacleQuery(BulletEnvironment& environment);
} // namespace masse::bridge
