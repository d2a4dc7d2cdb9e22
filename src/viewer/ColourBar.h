#pragma once
/// The colour bar beside a sheet coloured by a scalar: the colour map from its lowest to its highest value, with the
/// values at both ends and the scalar's unit, or, for a scalar the scene lacks, the reason it is drawn grey. No GL:
/// the panel draws it with ImGui, the tests read it.

#include "MassScalars.h"
#include "Palette.h"

#include <optional>
#include <string>
#include <vector>

namespace masse::viewer
{
struct ColourBar
{
    std::string title;      ///< the scalar and its unit, e.g. "speed (m/s)"
    std::string lowLabel;   ///< the value at the bar's left end, with its unit
    std::string highLabel;  ///< at its right end
    std::vector<Rgb> stops; ///< evenly spaced colours from low to high (empty when the scalar is missing)
    std::string note;       ///< why there is no bar ("" when there is one)
};

/// The unit as the bar shows it: the scalar's own, or "ratio" for a dimensionless one.
std::string unitLabel(const MassScalar& scalar);

/// The bar for `scalar` over `range` (the values last drawn); `missing`: why the scene lacks it ("" if it has it).
/// Without a range yet (nothing drawn) the bar says it is waiting for values.
ColourBar makeColourBar(const MassScalar& scalar, const std::optional<ScalarRange>& range, const std::string& missing,
                        int stops = 16);
} // namespace masse::viewer
