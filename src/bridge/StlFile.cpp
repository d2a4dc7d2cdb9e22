#include "StlFile.h"

#include "core/InputError.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace masse::bridge
{
namespace
{
/// Welds vertices with identical coordinates while triangles are added.
class MeshBuilder
{
public:
    void addTriangle(const std::array<Vec3, 3>& corners)
    {
        std::vector<int> face;
        for (const Vec3& v : corners)
        {
            const std::array<Real, 3> key{v.x(), v.y(), v.z()};
            auto [it, added] = m_index.try_emplace(key, int(m_mesh.vertices.size()));
            if (added)
            {
                m_mesh.vertices.push_back(v);
            }
            face.push_back(it->second);
        }
        m_mesh.faces.push_back(std::move(face));
    }
    PolygonMesh take() { return std::move(m_mesh); }

private:
    PolygonMesh m_mesh;
    std::map<std::array<Real, 3>, int> m_index;
};

std::string lower(std::string text)
{
    std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return char(std::tolower(c)); });
    return text;
}

PolygonMesh readBinary(const std::string& bytes, std::uint32_t count, const std::string& where)
{
    MeshBuilder builder;
    for (std::uint32_t t = 0; t < count; ++t)
    {
        const char* record = bytes.data() + 84 + std::size_t(t) * 50;
        std::array<Vec3, 3> corners;
        for (int k = 0; k < 3; ++k)
        {
            float xyz[3];
            std::memcpy(xyz, record + 12 + 12 * k, sizeof(xyz)); // little-endian IEEE floats, as on every target
            corners[std::size_t(k)] = Vec3(xyz[0], xyz[1], xyz[2]);
            if (!corners[std::size_t(k)].allFinite())
            {
                throw InputError(where + ": triangle " + std::to_string(t + 1) +
                                 " has a vertex that is not a finite number");
            }
        }
        builder.addTriangle(corners);
    }
    return builder.take();
}

PolygonMesh readAscii(const std::string& text, const std::string& where)
{
    MeshBuilder builder;
    std::istringstream in(text);
    std::string line;
    int lineNumber = 0;
    std::array<Vec3, 3> corners;
    int vertices = -1; // -1: outside a facet's loop
    bool solid = false;
    bool ended = false;
    auto fail = [&](const std::string& message) -> void
    { throw InputError(where + ", line " + std::to_string(lineNumber) + ": " + message); };
    while (std::getline(in, line))
    {
        ++lineNumber;
        std::istringstream words(line);
        std::string word;
        if (!(words >> word))
        {
            continue;
        }
        word = lower(word);
        if (!solid)
        {
            if (word != "solid")
            {
                fail("expected 'solid' to start an ASCII STL file (got '" + word + "')");
            }
            solid = true;
            continue;
        }
        if (ended)
        {
            fail("text after 'endsolid'");
        }
        if (word == "facet" || word == "endfacet" || word == "outer")
        {
            if (word == "outer")
            {
                if (vertices != -1)
                {
                    fail("'outer loop' inside a loop");
                }
                vertices = 0;
            }
            continue;
        }
        if (word == "vertex")
        {
            if (vertices < 0 || vertices >= 3)
            {
                fail(vertices < 0 ? "'vertex' outside 'outer loop'" : "a loop with more than 3 vertices");
            }
            std::array<std::string, 3> fields;
            if (!(words >> fields[0] >> fields[1] >> fields[2]))
            {
                fail("'vertex' needs three numbers");
            }
            Vec3 v;
            for (int k = 0; k < 3; ++k)
            {
                const std::string& field = fields[std::size_t(k)];
                char* end = nullptr;
                v[k] = std::strtod(field.c_str(), &end);
                if (end == field.c_str() || *end != '\0')
                {
                    fail("'" + field + "' is not a number");
                }
                if (!std::isfinite(v[k]))
                {
                    fail("vertex coordinate '" + field + "' is not a finite number");
                }
            }
            corners[std::size_t(vertices++)] = v;
            continue;
        }
        if (word == "endloop")
        {
            if (vertices != 3)
            {
                fail("a loop needs exactly 3 vertices (got " + std::to_string(std::max(vertices, 0)) + ")");
            }
            builder.addTriangle(corners);
            vertices = -1;
            continue;
        }
        if (word == "endsolid")
        {
            if (vertices != -1)
            {
                fail("'endsolid' inside a loop");
            }
            ended = true;
            continue;
        }
        fail("unexpected '" + word + "'");
    }
    if (!solid)
    {
        throw InputError(where + " is empty");
    }
    if (!ended)
    {
        throw InputError(where + ", line " + std::to_string(lineNumber) + ": the file ends before 'endsolid'");
    }
    return builder.take();
}
} // namespace

PolygonMesh loadStl(const std::string& path, const std::string& owner)
{
    const std::string where = "obstacle '" + owner + "': mesh file '" + path + "'";
    requireMeshFile(path, where);
    std::ifstream in(path, std::ios::binary);
    std::ostringstream buffer;
    buffer << in.rdbuf();
    if (!in.good() && !in.eof())
    {
        throw InputError(where + " cannot be read");
    }
    const std::string bytes = buffer.str();
    PolygonMesh mesh;
    std::uint32_t count = 0;
    if (bytes.size() >= 84)
    {
        std::memcpy(&count, bytes.data() + 80, sizeof(count));
    }
    if (bytes.size() >= 84 && bytes.size() == 84 + 50 * std::uint64_t(count))
    {
        mesh = readBinary(bytes, count, where);
    }
    else
    {
        std::string start = lower(bytes.substr(0, 5));
        if (start != "solid")
        {
            throw InputError(where + " does not parse: neither binary STL (" + std::to_string(bytes.size()) +
                             " bytes, where " + std::to_string(count) + " triangles need " +
                             std::to_string(84 + 50 * std::uint64_t(count)) +
                             ") nor ASCII STL (which starts with 'solid')");
        }
        mesh = readAscii(bytes, where);
    }
    if (mesh.faces.empty())
    {
        throw InputError(where + " has no triangles");
    }
    return mesh;
}

PolygonMesh loadMeshFile(const std::string& path, const std::string& owner)
{
    const std::string extension = lower(std::filesystem::path(path).extension().string());
    return extension == ".stl" ? loadStl(path, owner) : loadObj(path, owner);
}
} // namespace masse::bridge
