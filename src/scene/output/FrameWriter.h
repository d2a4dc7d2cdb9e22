#pragma once
/// Snapshots of the sheet: VTK XML PolyData (.vtp, opens in ParaView and VTK) and Wavefront OBJ.
///
/// Every point array's name ends in its unit, so ParaView's colour legend says what it shows: velocity_m_s,
/// speed_m_s, strain (dimensionless), temperature_C, thickness_m; pinned is 0 or 1; contact_obstacle is the index
/// of the obstacle a mass touches (-1 none) into the field-data table obstacle_names; self_contact (scenes with
/// contact.self_collision) is 1 for a mass in a pair of the sheet touching itself at the last substep, else 0. The
/// field TimeValue carries the simulated time (s), which ParaView and VTK readers take as the dataset's time.

#include "core/MassSpringSystem.h"
#include "core/lattice/LatticeSurface.h"

#include <cstdint>
#include <string>
#include <vector>

namespace masse::scene
{
/// Per-mass values and the frame's context (each per-mass array one value per mass; empty arrays are skipped).
struct FrameFields
{
    Real time = 0;                          ///< s, simulated
    std::vector<int> contactObstacle;       ///< the obstacle each mass touches, -1 none
    std::vector<std::string> obstacleNames; ///< name of obstacle i, for contactObstacle
    std::vector<std::uint8_t> selfContact;  ///< 1 where the sheet touches itself (empty: no self-collision)
    std::vector<std::pair<std::string, std::vector<double>>> scalars; ///< more per-mass scalars, by name and unit
};

/// VTK XML PolyData: the masses as points, the springs as lines, the bottom layer's surface as triangles, and per
/// mass: velocity, speed, strain, pinned, contact obstacle and any extra scalars.
std::string toVtp(const MassSpringSystem& system, const std::vector<Triangle>& surface, const FrameFields& fields);
/// OBJ: the masses as vertices, the bottom layer's surface as faces and, with `springs`, every spring as a line.
std::string toObj(const MassSpringSystem& system, const std::vector<Triangle>& surface, const std::string& name,
                  bool springs);
/// Mean relative stretch (|d| - s) / s of the springs at each mass; negative when compressed, 0 for a lone mass.
std::vector<double> meanSpringStrain(const MassSpringSystem& system);
} // namespace masse::scene
