#pragma once
/// An obstacle as VTK XML PolyData, so ParaView shows the sheet with what it lies on: the polyhedron's faces as
/// polygons in the room frame at a pose, the cell array face (the face number contact reports use), and field data
/// obstacle_name, obstacle_index (as in the sheet's contact_obstacle) and, for a moving obstacle's frame, TimeValue
/// (s). A still obstacle's one file is shared by every frame, so it has no time.

#include "bridge/KinematicPath.h"
#include "bridge/ObstacleGeometry.h"

#include <optional>
#include <string>

namespace masse::scene
{
std::string obstacleToVtp(const bridge::ObstacleGeometry& geometry, const bridge::Pose& pose, const std::string& name,
                          int index, std::optional<Real> time);
} // namespace masse::scene
