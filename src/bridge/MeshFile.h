#pragma once
/// Polygon meshes read from Wavefront OBJ files (tinyobjloader).

#include "core/Types.h"

#include <string>
#include <vector>

namespace masse::bridge
{
struct PolygonMesh
{
    std::vector<Vec3> vertices;
    std::vector<std::vector<int>> faces; ///< vertex indices of each face, in file order
};

/// Reads every face of every object in the file; throws InputError naming `owner` (the obstacle) and the file when
/// it is missing, does not parse, has no faces, or a face with fewer than three vertices.
PolygonMesh loadObj(const std::string& path, const std::string& owner);
} // namespace masse::bridge
