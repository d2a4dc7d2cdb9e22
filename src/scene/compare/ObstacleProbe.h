#pragma once
/// The obstacles of a scene as CompareMetrics sees them: signed distances of mass centres and a segment test, at the
/// obstacles' current poses (call setTime first for kinematic ones), through the core's ContactDetector interface (the
/// Bullet bridge implements it). Measuring MaSSE's masses and the twin's nodes with these same functions is what makes
/// their penetration and tunnel figures comparable.

#include "scene/compare/CompareMetrics.h"

#include "core/contact/Contact.h"

namespace masse::scene
{
/// Signed distance (m) of each point to the nearest obstacle surface, negative inside a solid (convex) obstacle.
/// Distances of `searchDistance` or more are reported as `searchDistance`: only the near ones matter to penetration.
std::vector<Real> signedDistances(ContactDetector& obstacles, const std::vector<Vec3>& points, Real searchDistance);

/// Segment test for TunnelCounter: a sweep of a 1 micrometre sphere (Bullet's convex sweep needs a volume) from one
/// end to the other.
ObstacleQuery obstacleQuery(ContactDetector& obstacles);
} // namespace masse::scene
