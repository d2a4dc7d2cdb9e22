#include "ColourBar.h"

#include <cstdio>

namespace masse::viewer
{
namespace
{
std::string formatValue(float value, const std::string& unit)
{
    char text[48];
    std::snprintf(text, sizeof text, "%.3g", double(value));
    return unit == "ratio" ? std::string(text) : std::string(text) + " " + unit;
}
} // namespace

std::string unitLabel(const MassScalar& scalar)
{
    return scalar.unit.empty() ? "ratio" : scalar.unit;
}

ColourBar makeColourBar(const MassScalar& scalar, const std::optional<ScalarRange>& range, const std::string& missing,
                        int stops)
{
    ColourBar bar;
    const std::string unit = unitLabel(scalar);
    bar.title = scalar.name + " (" + unit + ")";
    if (!missing.empty())
    {
        bar.note = missing + "; the sheet is drawn grey";
        return bar;
    }
    if (!range)
    {
        bar.note = "waiting for values";
        return bar;
    }
    for (int k = 0; k < stops; ++k)
    {
        bar.stops.push_back(viridis(stops > 1 ? float(k) / float(stops - 1) : 0.0f));
    }
    bar.lowLabel = formatValue(range->low, unit);
    bar.highLabel = formatValue(range->high, unit);
    return bar;
}
} // namespace masse::viewer
