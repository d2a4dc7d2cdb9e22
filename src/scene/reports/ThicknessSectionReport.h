#pragma once
/// report.thickness_section: the thickness along a section of the formed part at the end (thickness_section.csv and
/// .png), the bottom-layer masses nearest a line along x or z. `masse converge` compares it between lattice sizes.

#include "scene/Scene.h"

#include <string>
#include <vector>

namespace masse::scene
{
/// The section's line: along `axis` (0: x, 2: z) through `through`.
struct SectionSettings
{
    int axis = 0;
    Vec3 through = Vec3::Zero();
};

/// The section the scene's report.thickness_section names, or nullptr when it names none.
const SectionSettings* sectionSettings(const SceneSpec& spec);

/// One point of a thickness section: a bottom-layer mass near the section line (chosen by its rest position, so the
/// section follows the material as it deforms).
struct SectionPoint
{
    Index mass;
    Real restCoordinate; ///< m, along the section axis at rest
    Vec3 position;       ///< m, now
    Real thickness;      ///< m, now
    Real ratio;          ///< h / h0
};

/// The section the scene's report asks for (needs a material and report.thickness_section; empty otherwise). Sorted
/// along the axis.
std::vector<SectionPoint> thicknessSection(const Scene& scene);
/// The section along the given line (needs a material; empty otherwise): the viewer's live section.
std::vector<SectionPoint> thicknessSection(const Scene& scene, const SectionSettings& section);
std::string sectionCsv(const std::vector<SectionPoint>& section);
/// A gnuplot script plotting h/h0 against the rest coordinate, reading the CSV at `csvPath`.
std::string sectionPlotScript(const std::string& csvPath, const std::string& title);
} // namespace masse::scene
