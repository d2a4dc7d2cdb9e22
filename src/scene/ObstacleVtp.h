#pragma once
/// An obstacle as VTK XML PolyData, so ParaView shows the sheet with what it lies on: the polyhedron's faces as
/// polygons in the room frame at a pose, the cell array face (the face number contact reports use), and field data
/// obstacle_name, obstacle_index (as in the sheet's contact_obstacle) and TimeValue (s).

#include "bridge/KinematicPath.h"
#include "bridge/ObstacleGeometry.h"

#include <string>

namespace masse::scene
{
std::string obstacleToVtp(const bridge::ObstacleGeometry& geometry, const bridge::Pose& pose, const std::string& name,
                          int index, Real time);
} // namespace masse::scene
