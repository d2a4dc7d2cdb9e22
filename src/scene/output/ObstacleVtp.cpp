#include "scene/output/ObstacleVtp.h"

#include "scene/output/VtkXml.h"

#include <sstream>

namespace masse::scene
{
std::string obstacleToVtp(const bridge::ObstacleGeometry& geometry, const bridge::Pose& pose, const std::string& name,
                          int index, std::optional<Real> time)
{
    std::ostringstream out;
    out << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"PolyData\" version=\"0.1\" byte_order=\"LittleEndian\">\n<PolyData>\n<FieldData>\n";
    if (time)
    {
        vtkxml::timeValue(out, *time);
    }
    vtkxml::stringArray(out, "obstacle_name", {name});
    out << "<Array type=\"Int32\" Name=\"obstacle_index\" NumberOfTuples=\"1\" format=\"ascii\">\n"
        << index << "\n</Array>\n</FieldData>\n";
    out << "<Piece NumberOfPoints=\"" << geometry.vertices.size()
        << "\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"" << geometry.faces.size()
        << "\">\n";
    out << "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (const Vec3& local : geometry.vertices)
    {
        vtkxml::triple(out, pose.orientation * local + pose.position);
        out << '\n';
    }
    out << "</DataArray>\n</Points>\n";
    out << "<CellData Scalars=\"face\">\n<DataArray type=\"Int32\" Name=\"face\" format=\"ascii\">\n";
    for (std::size_t f = 0; f < geometry.faces.size(); ++f)
    {
        out << f << '\n';
    }
    out << "</DataArray>\n</CellData>\n";
    out << "<Polys>\n<DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n";
    for (const bridge::Face& face : geometry.faces)
    {
        for (std::size_t k = 0; k < face.vertices.size(); ++k)
        {
            out << (k ? " " : "") << face.vertices[k];
        }
        out << '\n';
    }
    out << "</DataArray>\n<DataArray type=\"Int32\" Name=\"offsets\" format=\"ascii\">\n";
    std::size_t offset = 0;
    for (const bridge::Face& face : geometry.faces)
    {
        offset += face.vertices.size();
        out << offset << '\n';
    }
    out << "</DataArray>\n</Polys>\n</Piece>\n</PolyData>\n</VTKFile>\n";
    return out.str();
}
} // namespace masse::scene
