#include "scene/reports/ThicknessSectionReport.h"

#include "scene/PlausibleRanges.h"
#include "scene/output/AtomicFile.h"
#include "scene/output/Plot.h"
#include "scene/reports/ReportRegistry.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace masse::scene
{
namespace
{
std::any readSection(const JsonObject& report)
{
    const JsonObject section = *report.object("thickness_section");
    SectionSettings settings;
    settings.axis = section.choice("axis", "x", {"x", "z"}) == "x" ? 0 : 2;
    settings.through = plausible::point(section, "through", Vec3::Zero());
    section.finish();
    return settings;
}

bool sectionDrawn(const SceneSpec& spec)
{
    return sectionSettings(spec) != nullptr;
}

class ThicknessSection final : public RunningReport
{
public:
    void write(Scene& scene, const std::string& directory, PlotBatch& plots) override
    {
        if (!scene.thickness())
        {
            return;
        }
        const std::string csv = directory + "/thickness_section.csv";
        writeFileAtomically(csv, sectionCsv(thicknessSection(scene)));
        plots.add(sectionPlotScript(csv, scene.spec().name), directory + "/thickness_section.png");
    }
};

} // namespace

extern const ReportEntry thicknessSectionReport = {
    .key = "thickness_section",
    .read = readSection,
    .enabled = sectionDrawn,
    .start = startReport<ThicknessSection>,
};

const SectionSettings* sectionSettings(const SceneSpec& spec)
{
    return reportSettings<SectionSettings>(spec, "thickness_section");
}

std::vector<SectionPoint> thicknessSection(const Scene& scene)
{
    const SectionSettings* section = sectionSettings(scene.spec());
    return section ? thicknessSection(scene, *section) : std::vector<SectionPoint>{};
}

std::vector<SectionPoint> thicknessSection(const Scene& scene, const SectionSettings& settings)
{
    std::vector<SectionPoint> points;
    const SheetThickness* thickness = scene.thickness();
    if (!thickness)
    {
        return points;
    }
    const SectionSettings* section = &settings;
    const Lattice& lattice = scene.lattice();
    const int along = section->axis;
    const int across = along == 0 ? 2 : 0;
    // The row (or column) of bottom-layer masses nearest the line, by rest position: within half the spacing across.
    const Real halfSpacing = 0.5 * (across == 2 ? lattice.spacingZ : lattice.spacingX) + 1e-12;
    const Real h0 = thickness->initialThickness();
    for (Index i = lattice.layerStart[0]; i < lattice.layerStart[1]; ++i)
    {
        const Vec3& rest = lattice.position[i];
        if (std::abs(rest[across] - section->through[across]) > halfSpacing)
        {
            continue;
        }
        const Real h = thickness->thickness()[i];
        points.push_back({i, rest[along], scene.system().particles.position[i], h, h / h0});
    }
    std::sort(points.begin(), points.end(),
              [](const SectionPoint& a, const SectionPoint& b) { return a.restCoordinate < b.restCoordinate; });
    return points;
}

std::string sectionCsv(const std::vector<SectionPoint>& section)
{
    std::ostringstream out;
    out << "mass,rest_coordinate_m,x_m,y_m,z_m,thickness_m,thickness_ratio\n";
    char line[200];
    for (const SectionPoint& p : section)
    {
        std::snprintf(line, sizeof(line), "%u,%.6f,%.6f,%.6f,%.6f,%.6e,%.6f\n", p.mass, p.restCoordinate,
                      p.position.x(), p.position.y(), p.position.z(), p.thickness, p.ratio);
        out << line;
    }
    return out.str();
}

std::string sectionPlotScript(const std::string& csvPath, const std::string& title)
{
    return "set datafile separator ','\n"
           "set title '" +
           title +
           ": thickness along the section'\n"
           "set xlabel 'position along the section at rest (m)'\n"
           "set ylabel 'thickness h / h0'\n"
           "set yrange [0:*]\n"
           "set grid\n"
           "plot '" +
           csvPath + "' every ::1 using 2:7 with linespoints pt 7 title 'h / h0'\n";
}
} // namespace masse::scene
