#pragma once
/// Snapshots of the sheet: VTK PolyData (.vtp, opens in ParaView) and Wavefront OBJ.

#include "core/LatticeSurface.h"
#include "core/MassSpringSystem.h"

#include <string>
#include <vector>

namespace masse::scene
{
/// Per-mass values written with a frame (each array one value per mass; empty arrays are skipped).
struct FrameFields
{
    std::vector<int> contactObstacle;                                 ///< the obstacle each mass touches, -1 none
    std::vector<std::pair<std::string, std::vector<double>>> scalars; ///< more per-mass scalars, by name
};

/// VTK XML PolyData: the masses as points, the springs as lines, the bottom layer's surface as triangles, and per
/// mass: velocity, speed, pinned, contact obstacle and any extra scalars.
std::string toVtp(const MassSpringSystem& system, const std::vector<Triangle>& surface, const FrameFields& fields);
/// OBJ: the masses as vertices and the bottom layer's surface as faces.
std::string toObj(const MassSpringSystem& system, const std::vector<Triangle>& surface, const std::string& name);
} // namespace masse::scene
