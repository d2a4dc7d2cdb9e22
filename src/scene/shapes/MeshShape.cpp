// obstacles[].type "mesh": the polygons of an OBJ or STL `file`, times `scale`; it may be concave and need not be
// closed. Its faces are numbered in the file's order. The file is read when the obstacle is made, not when the scene
// is.

#include "scene/shapes/ShapeRegistry.h"

#include "scene/PlausibleRanges.h"

#include "bridge/StlFile.h"

#include "core/Format.h"

#include <filesystem>

namespace masse::scene
{
namespace
{
struct MeshSource
{
    std::string path; ///< resolved against the scene file's folder
    Real scale = 1;   ///< applied to the file's coordinates
};

std::any readMesh(const JsonObject& o, const std::string& baseDirectory)
{
    MeshSource mesh;
    const std::filesystem::path file = o.string("file");
    mesh.path = file.is_absolute() ? file.string() : (std::filesystem::path(baseDirectory) / file).string();
    mesh.scale = o.positive("scale", 1.0);
    if (mesh.scale > plausible::maxMeshScale)
    {
        o.fail("scale",
               "must be in (0, " + formatNumber(plausible::maxMeshScale) + "] (got " + formatNumber(mesh.scale) + ")");
    }
    return mesh;
}

bridge::ObstacleShape meshSolid(const std::any& parameters, const std::string& obstacle)
{
    const MeshSource& mesh = std::any_cast<const MeshSource&>(parameters);
    bridge::ObstacleShape solid;
    solid.kind = bridge::SolidKind::Mesh;
    solid.polygons = bridge::loadMeshFile(mesh.path, obstacle);
    for (Vec3& v : solid.polygons.vertices)
    {
        v = mesh.scale * v;
    }
    return solid;
}

Real meshReach(const std::any& parameters)
{
    return 10 * std::any_cast<const MeshSource&>(parameters).scale; // the file is not read here: a generous size
}

std::string meshFile(const std::any& parameters)
{
    return std::any_cast<const MeshSource&>(parameters).path;
}
} // namespace

extern const ShapeEntry meshShape = {
    .name = "mesh",
    .closed = false,
    .read = readMesh,
    .solid = meshSolid,
    .reach = meshReach,
    .file = meshFile,
};
} // namespace masse::scene
