#pragma once
/// Per-mass scalars the sheet can be coloured by, registered by name. Speed and strain come with the viewer; a
/// model that adds a field (temperature, thickness) registers a provider under its name and the panel lists it.

#include "scene/Scene.h"

#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace masse::viewer
{
/// Smallest and largest of the values; a range of width zero is widened so colouring never divides by zero.
struct ScalarRange
{
    float low = 0;
    float high = 1;
    float normalise(float value) const { return (value - low) / (high - low); }
};
struct MassScalar
{
    std::string name;        ///< the key shown in the panel and given to --scalar, e.g. "speed"
    std::string unit;        ///< e.g. "m/s"; "" for a ratio
    std::string description; ///< one line for the panel's tooltip
    /// Fills one value per mass of the scene's sheet.
    std::function<void(const scene::Scene& scene, std::vector<float>& values)> evaluate;
    /// The colour bar's fixed span for this scene (thickness: 0 to h0, so a thinning of a few per cent does not fill
    /// the bar), or none: the bar then spans the values drawn.
    std::function<std::optional<ScalarRange>(const scene::Scene& scene)> fixedRange = {};
};

class MassScalarRegistry
{
public:
    /// Adds a scalar, or replaces the one with the same name.
    void add(MassScalar scalar);
    const MassScalar* find(std::string_view name) const;
    const std::vector<MassScalar>& all() const { return m_scalars; }
    /// The names, comma separated (for messages).
    std::string names() const;

private:
    std::vector<MassScalar> m_scalars;
};

/// speed (|v|, m/s), strain (mean relative stretch of the springs at each mass; negative when compressed),
/// temperature (C, heat scenes), thickness (mm) and thickness_ratio (h / h0) (material scenes).
MassScalarRegistry standardMassScalars();

/// Mean (length - rest) / rest over the springs of each mass (0 for a mass without springs).
void meanSpringStrain(const MassSpringSystem& system, std::vector<float>& values);

ScalarRange rangeOf(const std::vector<float>& values);
} // namespace masse::viewer
