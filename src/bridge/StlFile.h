#pragma once
/// Triangle meshes read from STL files, binary or ASCII (a small reader: Debian's assimp would bring some forty
/// formats and their dependencies for this one; tinyobjloader reads OBJ only).
///
/// STL stores every triangle with its own three vertices; the reader welds vertices with bit-identical coordinates,
/// so neighbouring triangles share them and the mesh's edges can be checked for a closed surface. The facet normals
/// in the file are ignored: the winding gives the normal, as for OBJ.

#include "MeshFile.h"

#include <string>

namespace masse::bridge
{
/// Reads an STL file. A file is binary when its size is 84 + 50 n bytes for the n triangles its header announces,
/// ASCII otherwise. Throws InputError naming `owner` (the obstacle), the file and, for ASCII, the line when the file
/// is missing, truncated, does not parse, has no triangles, or a vertex that is not a finite number.
PolygonMesh loadStl(const std::string& path, const std::string& owner);

/// Reads an OBJ or STL file, by its extension (.stl, any case, is STL; everything else OBJ).
PolygonMesh loadMeshFile(const std::string& path, const std::string& owner);
} // namespace masse::bridge
