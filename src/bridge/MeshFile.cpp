#include "MeshFile.h"

#include "core/InputError.h"

#include <tiny_obj_loader.h>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>

namespace masse::bridge
{
namespace
{
/// The whitespace-separated words of a line after its tag.
std::vector<std::string> words(const std::string& line)
{
    std::istringstream in(line);
    std::vector<std::string> result;
    std::string word;
    while (in >> word)
    {
        result.push_back(word);
    }
    return result;
}

/// Checks what tinyobjloader would read wrongly or with undefined behaviour before it reads the file: it takes "nan"
/// and "inf" for 0 silently, and casts a `vw` line's vertex number from a float to an int unchecked. Also counts the
/// triangles Bullet will index (a face of n vertices makes n - 2), refusing more than it can address.
void checkObjText(const std::string& path, const std::string& where)
{
    std::ifstream in(path);
    if (!in)
    {
        throw InputError(where + " cannot be read");
    }
    std::string line;
    std::size_t lineNumber = 0;
    std::size_t triangles = 0;
    while (std::getline(in, line))
    {
        ++lineNumber;
        const std::vector<std::string> w = words(line);
        if (w.empty())
        {
            continue;
        }
        const std::string at = where + ", line " + std::to_string(lineNumber);
        if (w[0] == "v")
        {
            if (w.size() < 4)
            {
                throw InputError(at + ": a vertex needs x, y and z");
            }
            for (std::size_t k = 1; k < w.size(); ++k)
            {
                char* end = nullptr;
                const double value = std::strtod(w[k].c_str(), &end); // an underflow to 0 is harmless
                if (end == w[k].c_str() || *end != '\0' || !std::isfinite(value))
                {
                    throw InputError(at + ": vertex coordinate '" + w[k] + "' is not a finite number");
                }
            }
        }
        else if (w[0] == "vw")
        {
            char* end = nullptr;
            errno = 0;
            const long vertex = w.size() < 2 ? -1 : std::strtol(w[1].c_str(), &end, 10);
            if (w.size() < 2 || end == w[1].c_str() || *end != '\0' || errno == ERANGE || vertex < 0 ||
                vertex > std::numeric_limits<int>::max())
            {
                throw InputError(at + ": a vertex weight (vw) needs a vertex number in [0, " +
                                 std::to_string(std::numeric_limits<int>::max()) + "]");
            }
        }
        else if (w[0] == "mtllib")
        {
            // tinyobjloader opens material libraries beside the file; a device or pipe there would never end.
            for (std::size_t k = 1; k < w.size(); ++k)
            {
                const std::filesystem::path library = std::filesystem::path(path).parent_path() / w[k];
                std::error_code error;
                if (std::filesystem::exists(library, error) && !std::filesystem::is_regular_file(library, error))
                {
                    throw InputError(at + ": material library '" + w[k] + "' is not a regular file");
                }
            }
        }
        else if (w[0] == "f" && w.size() < 4)
        {
            // tinyobjloader drops such a face without a word: the mesh would lack it.
            throw InputError(at + ": a face needs at least 3 vertices (got " + std::to_string(w.size() - 1) + ")");
        }
        else if (w[0] == "f")
        {
            triangles += w.size() - 3;
            if (triangles > maxMeshTriangles)
            {
                throw InputError(at + ": more than " + std::to_string(maxMeshTriangles) +
                                 " triangles (after splitting faces into triangles), the most one mesh obstacle may "
                                 "have (Bullet indexes at most 2^21 per mesh); simplify the mesh");
            }
        }
    }
}
} // namespace

void requireMeshFile(const std::string& path, const std::string& where)
{
    std::error_code error;
    const std::filesystem::file_status status = std::filesystem::status(path, error);
    if (error && error.value() == ELOOP)
    {
        throw InputError(where + " is a symbolic link that leads back to itself (a loop): link it to the mesh file");
    }
    if (error || !std::filesystem::exists(status))
    {
        throw InputError(where + " does not exist");
    }
    if (!std::filesystem::is_regular_file(status))
    {
        throw InputError(where + " is not a regular file");
    }
}

PolygonMesh loadObj(const std::string& path, const std::string& owner)
{
    const std::string where = "obstacle '" + owner + "': mesh file '" + path + "'";
    requireMeshFile(path, where);
    checkObjText(path, where);
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
