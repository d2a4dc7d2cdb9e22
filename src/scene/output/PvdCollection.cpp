#include "scene/output/PvdCollection.h"

#include "scene/output/VtkXml.h"

#include <sstream>

namespace masse::scene
{
void PvdCollection::add(Real time, int part, const std::string& name, const std::string& file)
{
    m_entries.push_back({time, part, name, file});
}

std::string PvdCollection::text() const
{
    std::ostringstream out;
    out << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n<Collection>\n";
    for (const Entry& e : m_entries)
    {
        out << "<DataSet timestep=\"";
        vtkxml::number(out, e.time);
        out << "\" group=\"\" part=\"" << e.part << "\" name=\"" << vtkxml::escaped(e.name) << "\" file=\""
            << vtkxml::escaped(e.file) << "\"/>\n";
    }
    out << "</Collection>\n</VTKFile>\n";
    return out.str();
}
} // namespace masse::scene
