#include "scene/output/FrameWriter.h"

#include "scene/output/VtkXml.h"

#include <sstream>

namespace masse::scene
{
namespace
{
using vtkxml::number;
using vtkxml::triple;

void scalarArray(std::ostringstream& out, const std::string& name, const std::vector<double>& values)
{
    out << "<DataArray type=\"Float64\" Name=\"" << vtkxml::escaped(name) << "\" format=\"ascii\">\n";
    for (double value : values)
    {
        number(out, value);
        out << '\n';
    }
    out << "</DataArray>\n";
}
} // namespace

std::vector<double> meanSpringStrain(const MassSpringSystem& system)
{
    const std::vector<Vec3>& x = system.particles.position;
    const SpringSet& springs = system.springs;
    std::vector<double> strain(x.size(), 0.0);
    std::vector<int> count(x.size(), 0);
    for (std::size_t s = 0; s < springs.size(); ++s)
    {
        const SpringEnds& e = springs.ends()[s];
        const Real rest = springs.restLength()[s];
        const Real stretch = ((x[e.a] - x[e.b]).norm() - rest) / rest;
        strain[e.a] += stretch;
        strain[e.b] += stretch;
        ++count[e.a];
        ++count[e.b];
    }
    for (std::size_t i = 0; i < strain.size(); ++i)
    {
        if (count[i] > 0)
        {
            strain[i] /= count[i];
        }
    }
    return strain;
}

std::string toVtp(const MassSpringSystem& system, const std::vector<Triangle>& surface, const FrameFields& fields)
{
    const Particles& p = system.particles;
    const SpringSet& s = system.springs;
    std::ostringstream out;
    out << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">\n<PolyData>\n<FieldData>\n";
    vtkxml::timeValue(out, fields.time);
    if (!fields.obstacleNames.empty())
    {
        vtkxml::stringArray(out, "obstacle_names", fields.obstacleNames);
    }
    out << "</FieldData>\n";
    out << "<Piece NumberOfPoints=\"" << p.size() << "\" NumberOfVerts=\"0\" NumberOfLines=\"" << s.size()
        << "\" NumberOfStrips=\"0\" NumberOfPolys=\"" << surface.size() << "\">\n";
    out << "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (const Vec3& x : p.position)
    {
        triple(out, x);
        out << '\n';
    }
    out << "</DataArray>\n</Points>\n";

    out << "<PointData Scalars=\"speed_m_s\" Vectors=\"velocity_m_s\">\n";
    out << "<DataArray type=\"Float64\" Name=\"velocity_m_s\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (const Vec3& v : p.velocity)
    {
        triple(out, v);
        out << '\n';
    }
    out << "</DataArray>\n";
    std::vector<double> speed;
    speed.reserve(p.size());
    for (const Vec3& v : p.velocity)
    {
        speed.push_back(v.norm());
    }
    scalarArray(out, "speed_m_s", speed);
    scalarArray(out, "strain", meanSpringStrain(system));
    out << "<DataArray type=\"Int32\" Name=\"pinned\" format=\"ascii\">\n";
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
    if (fields.selfContact.size() == p.size())
    {
        out << "<DataArray type=\"Int32\" Name=\"self_contact\" format=\"ascii\">\n";
        for (std::uint8_t touching : fields.selfContact)
        {
            out << int(touching) << '\n';
        }
        out << "</DataArray>\n";
    }
    for (const auto& [name, values] : fields.scalars)
    {
        if (values.size() == p.size())
        {
            scalarArray(out, name, values);
        }
    }
    out << "</PointData>\n";

    out << "<Lines>\n<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n";
    for (const SpringEnds& e : s.ends())
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

std::string toObj(const MassSpringSystem& system, const std::vector<Triangle>& surface, const std::string& name,
                  bool springs)
{
    std::ostringstream out;
    out << "# MaSSE sheet frame: the masses as vertices, the bottom layer's surface as faces"
        << (springs ? ", the springs as lines\n" : "\n");
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
    if (springs)
    {
        for (const SpringEnds& e : system.springs.ends())
        {
            out << "l " << e.a + 1 << ' ' << e.b + 1 << '\n';
        }
    }
    return out.str();
}
} // namespace masse::scene
