#pragma once
/// Polygon meshes read from Wavefront OBJ files (tinyobjloader).

#include "core/Types.h"

#include <cstddef>
#include <string>
#include <vector>

namespace masse::bridge
{
/// The most triangles (each face of n vertices makes n - 2) a mesh may have: Bullet's quantized BVH gives a triangle's
/// index 21 bits, and past 2^21 it indexes other memory.
constexpr std::size_t maxMeshTriangles = std::size_t(1) << 21;

struct PolygonMesh
{
    std::vector<Vec3> vertices;
    std::vector<std::vector<int>> faces; ///< vertex indices of each face, in file order
};

/// Throws InputError "<where> does not exist" (or is a loop of symbolic links, or is not a regular file) unless
/// `path` leads to a regular file: a filesystem error never reaches the user raw.
void requireMeshFile(const std::string& path, const std::string& where);

/// Reads every face of every object in the file; throws InputError naming `owner` (the obstacle) and the file when
/// it is missing, does not parse, has no faces, or a face with fewer than three vertices, and naming the line of a
/// vertex that is not a finite number or of the face past maxMeshTriangles.
PolygonMesh loadObj(const std::string& path, const std::string& owner);
} // namespace masse::bridge
