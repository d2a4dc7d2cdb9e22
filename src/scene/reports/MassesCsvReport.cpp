// report.masses_csv: every mass at the end in masses.csv: index, layer, position (m), thickness (m) and h/h0 (with a
// material), temperature (C, with heat) and the obstacle it touched in the last frame ("" if none).

#include "scene/reports/ReportRegistry.h"

#include "scene/output/AtomicFile.h"

#include "core/material/Material.h"

#include <cstdio>
#include <sstream>

namespace masse::scene
{
namespace
{
std::any readMassesCsv(const JsonObject& report)
{
    return report.boolean("masses_csv", false);
}

bool massesCsvWritten(const SceneSpec& spec)
{
    const bool* written = reportSettings<bool>(spec, "masses_csv");
    return written && *written;
}

std::string massesCsv(Scene& scene)
{
    const Particles& p = scene.system().particles;
    const SheetThickness* thickness = scene.thickness();
    const ThermalModel* thermal = scene.thermal();
    const std::vector<int>& touching = scene.contact().report().touchingObstacle();
    std::ostringstream out;
    out << "mass,layer,x_m,y_m,z_m,thickness_m,thickness_ratio,temperature_c,contact\n";
    char line[256];
    for (std::size_t i = 0; i < p.size(); ++i)
    {
        const Vec3& x = p.position[i];
        std::snprintf(line, sizeof(line), "%zu,%d,%.6f,%.6f,%.6f,", i, scene.lattice().coord[i].layer, x.x(), x.y(),
                      x.z());
        out << line;
        if (thickness)
        {
            std::snprintf(line, sizeof(line), "%.6e,%.5f,", thickness->thickness()[i],
                          thickness->thickness()[i] / thickness->initialThickness());
            out << line;
        }
        else
        {
            out << ",,";
        }
        if (thermal)
        {
            std::snprintf(line, sizeof(line), "%.3f,", kelvinToCelsius(thermal->temperature()[i]));
            out << line;
        }
        else
        {
            out << ',';
        }
        const int obstacle = i < touching.size() ? touching[i] : -1;
        if (obstacle >= 0)
        {
            out << '"' << scene.environment().obstacle(obstacle).name << '"';
        }
        out << '\n';
    }
    return out.str();
}

class MassesCsv final : public RunningReport
{
public:
    void write(Scene& scene, const std::string& directory, PlotBatch& /*plots*/) override
    {
        writeFileAtomically(directory + "/masses.csv", massesCsv(scene));
    }
};

} // namespace

extern const ReportEntry massesCsvReport = {
    .key = "masses_csv",
    .read = readMassesCsv,
    .enabled = massesCsvWritten,
    .start = startReport<MassesCsv>,
};
} // namespace masse::scene
