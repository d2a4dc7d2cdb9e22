#include "scene/output/VtkXml.h"

#include <cstdio>

namespace masse::scene::vtkxml
{
void number(std::ostringstream& out, double value)
{
    char buffer[32];
    std::snprintf(buffer, sizeof(buffer), "%.9g", value);
    out << buffer;
}

void triple(std::ostringstream& out, const Vec3& v)
{
    number(out, v.x());
    out << ' ';
    number(out, v.y());
    out << ' ';
    number(out, v.z());
}

std::string escaped(const std::string& text)
{
    std::string out;
    for (char c : text)
    {
        switch (c)
        {
        case '&':
            out += "&amp;";
            break;
        case '<':
            out += "&lt;";
            break;
        case '>':
            out += "&gt;";
            break;
        case '"':
            out += "&quot;";
            break;
        default:
            out += c;
        }
    }
    return out;
}

void stringArray(std::ostringstream& out, const std::string& name, const std::vector<std::string>& values)
{
    out << "<Array type=\"String\" Name=\"" << escaped(name) << "\" NumberOfTuples=\"" << values.size()
        << "\" format=\"ascii\">\n";
    for (const std::string& value : values)
    {
        for (unsigned char c : value)
        {
            out << int(c) << ' ';
        }
        out << "0\n";
    }
    out << "</Array>\n";
}

void timeValue(std::ostringstream& out, Real seconds)
{
    out << "<Array type=\"Float64\" Name=\"TimeValue\" NumberOfTuples=\"1\" format=\"ascii\">\n";
    number(out, seconds);
    out << "\n</Array>\n";
}
} // namespace masse::scene::vtkxml
