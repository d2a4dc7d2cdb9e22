#include "MeshFile.h"

#include "core/InputError.h"

#include <tiny_obj_loader.h>

#include <filesystem>

namespace masse::bridge
{
PolygonMesh loadObj(const std::string& path, const std::string& owner)
{
    const std::string where = "obstacle '" + owner + "': mesh file '" + path + "'";
    if (!std::filesystem::is_regular_file(path))
    {
        throw InputError(where + " does not exist");
    }
    tinyobj::ObjReaderConfig config;
    config.triangulate = false; // keep the file's own faces: contact reports name them
    config.vertex_color = false;
    tinyobj::ObjReader reader;
    if (!reader.ParseFromFile(path, config) || !reader.Valid())
    {
        std::string error = reader.Error();
        while (!error.empty() && (error.back() == '\n' || error.back() == '\r'))
        {
            error.pop_back();
        }
        throw InputError(where + " does not parse" + (error.empty() ? std::string() : ": " + error));
    }
    const tinyobj::attrib_t& attrib = reader.GetAttrib();
    PolygonMesh mesh;
    for (std::size_t i = 0; i + 2 < attrib.vertices.size(); i += 3)
    {
        mesh.vertices.emplace_back(attrib.vertices[i], attrib.vertices[i + 1], attrib.vertices[i + 2]);
    }
    for (const tinyobj::shape_t& shape : reader.GetShapes())
    {
        std::size_t next = 0;
        for (const auto count : shape.mesh.num_face_vertices)
        {
            if (count < 3)
            {
                throw InputError(where + ": face " + std::to_string(mesh.faces.size() + 1) +
                                 " has fewer than 3 vertices");
            }
            std::vector<int> face;
            for (std::size_t k = 0; k < count; ++k)
            {
                const int index = shape.mesh.indices[next + k].vertex_index;
                if (index < 0 || std::size_t(index) >= mesh.vertices.size())
                {
                    throw InputError(where + ": face " + std::to_string(mesh.faces.size() + 1) +
                                     " names a vertex that does not exist");
                }
                face.push_back(index);
            }
            next += count;
            mesh.faces.push_back(std::move(face));
        }
    }
    if (mesh.faces.empty())
    {
        throw InputError(where + " has no faces");
    }
    for (const Vec3& v : mesh.vertices)
    {
        if (!v.allFinite())
        {
            throw InputError(where + " has a vertex that is not a finite number");
        }
    }
    return mesh;
}
} // namespace masse::bridge
