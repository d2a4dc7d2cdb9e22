#pragma once
/// Numbers in messages and reports.

#include "core/Types.h"

#include <cstdio>
#include <sstream>
#include <string>

namespace masse
{
/// The shortest plain form of a number ("0.03", "1e-05"), for error messages.
inline std::string formatNumber(Real value)
{
    std::ostringstream out;
    out << value;
    return out.str();
}

/// A number through a printf format ("%.3g"), for tables.
inline std::string formatNumber(const char* format, double value)
{
    char text[64];
    std::snprintf(text, sizeof(text), format, value);
    return text;
}
} // namespace masse
