#include "scene/reports/WebbingReport.h"

#include "scene/output/AtomicFile.h"
#include "scene/reports/ReportRegistry.h"

#include "bridge/SelfContactTree.h"

#include <cstdio>
#include <sstream>

namespace masse::scene
{
namespace
{
std::any readWebbing(const JsonObject& report)
{
    return report.boolean("webbing", false);
}

class Webbing final : public RunningReport
{
public:
    void summarize(const Scene& scene, nlohmann::json& summary) override
    {
        m_places = webbingPlaces(scene); // from finite positions only: the broadphase's boxes need them
        summary["webbing"] = webbingSummary(m_places, webbingDistance(scene.spec()));
        summary["final"]["webbing_masses"] = summary["webbing"]["masses"]; // for an expect block
    }

    void write(Scene&, const std::string& directory, PlotBatch&) override
    {
        writeFileAtomically(directory + "/webbing.csv", webbingCsv(m_places));
    }

private:
    std::vector<WebbingPlace> m_places;
};

constexpr std::string_view webbingSummaryKeys[] = {"webbing", "final.webbing_masses"};
} // namespace

extern const ReportEntry webbingReport = {
    .key = "webbing",
    .read = readWebbing,
    .enabled = reportsWebbing,
    .start = startReport<Webbing>,
    .summaryKeys = webbingSummaryKeys,
};

bool reportsWebbing(const SceneSpec& spec)
{
    const bool* asked = reportSettings<bool>(spec, "webbing");
    return asked ? *asked : spec.forming.enabled || spec.material.enabled || spec.selfCollision;
}

Real webbingDistance(const SceneSpec& spec)
{
    return 1.5 * spec.contact.radius;
}

std::vector<WebbingPlace> webbingPlaces(const Scene& scene)
{
    // A self-contact of its own, so that asking its broadphase leaves the run's (if any) as it was.
    bridge::SelfContactTree tree;
    SelfContactSettings settings;
    settings.radius = scene.spec().contact.radius;
    SelfContact surface(scene.lattice(), tree, settings, SelfContact::Exclusions::SpringsOnly);
    return findWebbing(surface, scene.lattice(), scene.system().particles.position, webbingDistance(scene.spec()));
}

std::string webbingCsv(const std::vector<WebbingPlace>& places)
{
    std::ostringstream out;
    out << "place,masses,centre_x_m,centre_y_m,centre_z_m,min_x_m,min_y_m,min_z_m,max_x_m,max_y_m,max_z_m,"
           "sheet_min_x_m,sheet_min_z_m,sheet_max_x_m,sheet_max_z_m\n";
    for (std::size_t k = 0; k < places.size(); ++k)
    {
        const WebbingPlace& p = places[k];
        char line[512];
        std::snprintf(line, sizeof(line), "%zu,%zu,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f,%.6f\n",
                      k + 1, p.masses.size(), p.centre.x(), p.centre.y(), p.centre.z(), p.low.x(), p.low.y(), p.low.z(),
                      p.high.x(), p.high.y(), p.high.z(), p.restLow.x(), p.restLow.z(), p.restHigh.x(), p.restHigh.z());
        out << line;
    }
    return out.str();
}

nlohmann::json webbingSummary(const std::vector<WebbingPlace>& places, Real distance)
{
    const auto vec = [](const Vec3& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); };
    nlohmann::json largest = nlohmann::json::array();
    std::size_t masses = 0;
    for (std::size_t k = 0; k < places.size(); ++k)
    {
        const WebbingPlace& p = places[k];
        masses += p.masses.size();
        if (k < 10)
        {
            largest.push_back({{"masses", p.masses.size()},
                               {"centre", vec(p.centre)},
                               {"min", vec(p.low)},
                               {"max", vec(p.high)},
                               {"sheet_min", {p.restLow.x(), p.restLow.z()}},
                               {"sheet_max", {p.restHigh.x(), p.restHigh.z()}}});
        }
    }
    return {{"distance_m", distance}, {"places", places.size()}, {"masses", masses}, {"largest", largest}};
}
} // namespace masse::scene
