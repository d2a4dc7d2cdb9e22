// report.sag: the sag of one mass against time (sag.csv and sag.png), how far it has dropped below where it started,
// recorded after every step; summary.json gets "sag" and final.sag, so that an expect block can bound it.

#include "scene/reports/ReportRegistry.h"

#include "scene/output/AtomicFile.h"
#include "scene/output/Plot.h"

#include <cstdio>
#include <limits>
#include <sstream>
#include <utility>

namespace masse::scene
{
namespace
{
struct SagSettings
{
    bool drawn = false;
    int mass = -1; ///< -1: the bottom-layer mass nearest the sheet's centre
};

std::any readSag(const JsonObject& report)
{
    SagSettings settings;
    const nlohmann::json& sag = *report.raw("sag");
    if (sag.is_boolean())
    {
        settings.drawn = sag.get<bool>();
        return settings;
    }
    const JsonObject s(sag, report.pathOf("sag"));
    settings.drawn = true;
    settings.mass = s.integer("mass", -1, -1, std::numeric_limits<int>::max());
    s.finish();
    return settings;
}

bool sagDrawn(const SceneSpec& spec)
{
    const SagSettings* settings = reportSettings<SagSettings>(spec, "sag");
    return settings && settings->drawn;
}

std::vector<NamedMass> sagMass(const SceneSpec& spec)
{
    const SagSettings* settings = reportSettings<SagSettings>(spec, "sag");
    if (!settings || !settings->drawn || settings->mass < 0)
    {
        return {};
    }
    return {{std::size_t(settings->mass), "report.sag.mass"}};
}

/// The bottom-layer mass nearest the middle of the sheet's box.
Index centreMass(const Lattice& lattice)
{
    const LatticeSpec& spec = lattice.spec;
    const Vec3 middle = 0.5 * (spec.minCorner + spec.maxCorner);
    Index nearest = 0;
    Real best = std::numeric_limits<Real>::infinity();
    for (Index i = lattice.layerStart[0]; i < lattice.layerStart[1]; ++i)
    {
        const Vec3 d = lattice.position[i] - middle;
        const Real distance = d.x() * d.x() + d.z() * d.z();
        if (distance < best)
        {
            best = distance;
            nearest = i;
        }
    }
    return nearest;
}

class Sag final : public RunningReport
{
public:
    explicit Sag(const Scene& scene)
    {
        const int asked = reportSettings<SagSettings>(scene.spec(), "sag")->mass;
        m_mass = asked >= 0 ? Index(asked) : centreMass(scene.lattice());
        m_startHeight = scene.system().particles.position[m_mass].y();
        m_series.emplace_back(scene.time(), 0.0);
    }

    void afterStep(const Scene& scene) override
    {
        m_series.emplace_back(scene.time(), m_startHeight - scene.system().particles.position[m_mass].y());
    }

    void summarize(const Scene&, nlohmann::json& summary) override
    {
        summary["sag"] = {{"mass", m_mass}, {"final", m_series.back().second}};
        summary["final"]["sag"] = m_series.back().second;
    }

    void write(Scene& scene, const std::string& directory, PlotBatch& plots) override
    {
        const std::string csv = directory + "/sag.csv";
        writeFileAtomically(csv, csvText());
        plots.add(plotScript(csv, scene.spec().name), directory + "/sag.png");
    }

private:
    std::string csvText() const
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

    static std::string plotScript(const std::string& csvPath, const std::string& title)
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

    Index m_mass = 0;
    Real m_startHeight = 0;
    std::vector<std::pair<Real, Real>> m_series; ///< (s, m)
};

std::unique_ptr<RunningReport> startSag(const Scene& scene)
{
    return std::make_unique<Sag>(scene);
}

constexpr std::string_view sagSummaryKeys[] = {"sag", "final.sag"};
} // namespace

extern const ReportEntry sagReport = {
    .key = "sag",
    .read = readSag,
    .enabled = sagDrawn,
    .start = startSag,
    .summaryKeys = sagSummaryKeys,
    .massesNamed = sagMass,
};
} // namespace masse::scene
