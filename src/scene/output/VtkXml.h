#pragma once
/// Pieces of VTK's XML file format (ASCII), shared by the sheet's frames, the obstacles and the .pvd collection.

#include "core/Types.h"

#include <sstream>
#include <string>
#include <vector>

namespace masse::scene::vtkxml
{
/// A number with 9 significant digits (enough to keep a double's meaning for viewing), as %.9g.
void number(std::ostringstream& out, double value);
/// "x y z" with number() for each.
void triple(std::ostringstream& out, const Vec3& v);
/// Text with &, <, >, " escaped, for an XML attribute.
std::string escaped(const std::string& text);
/// A field-data string array: VTK writes each string as its character codes followed by a 0.
void stringArray(std::ostringstream& out, const std::string& name, const std::vector<std::string>& values);
/// The field-data array TimeValue (one Float64): the dataset's time as ParaView and VTK's readers understand it.
void timeValue(std::ostringstream& out, Real seconds);
} // namespace masse::scene::vtkxml
