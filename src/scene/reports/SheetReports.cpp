#include "scene/reports/SheetReports.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

namespace masse::scene
{
std::vector<SectionPoint> thicknessSection(const Scene& scene)
{
    std::vector<SectionPoint> points;
    const SheetThickness* thickness = scene.thickness();
    if (!thickness)
    {
        return points;
    }
    const Lattice& lattice = scene.lattice();
    const ReportSpec& report = scene.spec().report;
    const int along = report.sectionAxis;
    const int across = along == 0 ? 2 : 0;
    // The row (or column) of bottom-layer masses nearest the line, by rest position: within half the spacing across.
    const Real halfSpacing = 0.5 * (across == 2 ? lattice.spacingZ : lattice.spacingX) + 1e-12;
    const Real h0 = thickness->initialThickness();
    for (Index i = lattice.layerStart[0]; i < lattice.layerStart[1]; ++i)
    {
        const Vec3& rest = lattice.position[i];
        if (std::abs(rest[across] - report.sectionThrough[across]) > halfSpacing)
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

SagRecorder::SagRecorder(const Scene& scene)
{
    const Lattice& lattice = scene.lattice();
    const int requested = scene.spec().report.sagMass;
    if (requested >= 0)
    {
        m_mass = Index(requested);
    }
    else
    {
        // The bottom-layer mass nearest the middle of the sheet's box.
        const LatticeSpec& spec = lattice.spec;
        const Vec3 middle = 0.5 * (spec.minCorner + spec.maxCorner);
        Real best = std::numeric_limits<Real>::infinity();
        for (Index i = lattice.layerStart[0]; i < lattice.layerStart[1]; ++i)
        {
            const Vec3 d = lattice.position[i] - middle;
            const Real distance = d.x() * d.x() + d.z() * d.z();
            if (distance < best)
            {
                best = distance;
                m_mass = i;
            }
        }
    }
    m_startHeight = scene.system().particles.position[m_mass].y();
    m_series.emplace_back(scene.time(), 0.0);
}

void SagRecorder::record(const Scene& scene)
{
    m_series.emplace_back(scene.time(), m_startHeight - scene.system().particles.position[m_mass].y());
}

std::string SagRecorder::csv() const
{
    std::ostringstream out;
    out << "time_s,sag_m\n";
    char line[64];
    for (const auto& [t, sag] : m_series)
    {
        std::snprintf(line, sizeof(line), "%.4f,%.6e\n", t, sag);
        out << line;
    }
    return out.str();
}

std::string SagRecorder::plotScript(const std::string& csvPath, const std::string& title)
{
    return "set datafile separator ','\n"
           "set title '" +
           title +
           ": sag of the sheet centre'\n"
           "set xlabel 'time (s)'\n"
           "set ylabel 'sag (mm)'\n"
           "set grid\n"
           "plot '" +
           csvPath + "' every ::1 using 1:($2*1000) with lines lw 2 title 'sag'\n";
}
} // namespace masse::scene
