#include "FrameWriter.h"

#include <cmath>
#include <cstdio>
#include <sstream>

namespace masse::scene
{
namespace
{
void number(std::ostringstream& out, double value)
{
    char buffer[32];
    std::snprintf(buffer, sizeof(buffer), "%.9g", value);
    out << buffer;
}

/// "x y z" with enough digits to read back the same doubles' meaning (9 significant).
void triple(std::ostringstream& out, const Vec3& v)
{
    number(out, v.x());
    out << ' ';
    number(out, v.y());
    out << ' ';
    number(out, v.z());
}
} // namespace

std::string toVtp(const MassSpringSystem& system, const std::vector<Triangle>& surface, const FrameFields& fields)
{
    const Particles& p = system.particles;
    const SpringSet& s = system.springs;
    std::ostringstream out;
    out << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">\n<PolyData>\n"
        << "<Piece NumberOfPoints=\"" << p.size() << "\" NumberOfVerts=\"0\" NumberOfLines=\"" << s.size()
        << "\" NumberOfStrips=\"0\" NumberOfPolys=\"" << surface.size() << "\">\n";
    out << "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (const Vec3& x : p.position)
    {
        triple(out, x);
        out << '\n';
    }
    out << "</DataArray>\n</Points>\n";

    out << "<PointData Scalars=\"speed\" Vectors=\"velocity\">\n";
    out << "<DataArray type=\"Float64\" Name=\"velocity\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (const Vec3& v : p.velocity)
    {
        triple(out, v);
        out << '\n';
    }
    out << "</DataArray>\n<DataArray type=\"Float64\" Name=\"speed\" format=\"ascii\">\n";
    for (const Vec3& v : p.velocity)
    {
        number(out, v.norm());
        out << '\n';
    }
    out << "</DataArray>\n<DataArray type=\"Int32\" Name=\"pinned\" format=\"ascii\">\n";
    for (std::uint8_t pinned : p.pinned)
    {
        out << int(pinned) << '\n';
    }
    out << "</DataArray>\n";
    if (fields.contactObstacle.size() == p.size())
    {
        out << "<DataArray type=\"Int32\" Name=\"contact_obstacle\" format=\"ascii\">\n";
        for (int o : fields.contactObstacle)
        {
            out << o << '\n';
        }
        out << "</DataArray>\n";
    }
    for (const auto& [name, values] : fields.scalars)
    {
        if (values.size() != p.size())
        {
            continue;
        }
        out << "<DataArray type=\"Float64\" Name=\"" << name << "\" format=\"ascii\">\n";
        for (double value : values)
        {
            number(out, value);
            out << '\n';
        }
        out << "</DataArray>\n";
    }
    out << "</PointData>\n";

    out << "<Lines>\n<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n";
    for (const SpringEnds& e : s.ends)
    {
        out << e.a << ' ' << e.b << '\n';
    }
    out << "</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n";
    for (std::size_t i = 1; i <= s.size(); ++i)
    {
        out << 2 * i << '\n';
    }
    out << "</DataArray>\n</Lines>\n";

    out << "<Polys>\n<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n";
    for (const Triangle& t : surface)
    {
        out << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
    }
    out << "</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n";
    for (std::size_t i = 1; i <= surface.size(); ++i)
    {
        out << 3 * i << '\n';
    }
    out << "</DataArray>\n</Polys>\n</Piece>\n</PolyData>\n</VTKFile>\n";
    return out.str();
}

std::string toObj(const MassSpringSystem& system, const std::vector<Triangle>& surface, const std::string& name)
{
    std::ostringstream out;
    out << "# MaSSE sheet frame: the masses as vertices, the bottom layer's surface as faces\n";
    out << "o " << name << '\n';
    for (const Vec3& x : system.particles.position)
    {
        out << "v ";
        triple(out, x);
        out << '\n';
    }
    for (const Triangle& t : surface)
    {
        out << "f " << t[0] + 1 << ' ' << t[1] + 1 << ' ' << t[2] + 1 << '\n';
    }
    return out.str();
}
} // namespace masse::scene
