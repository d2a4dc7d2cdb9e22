#include "core/Format.h"
#include "scene/compare/Comparison.h"

#include "scene/output/AtomicFile.h"
#include "scene/output/Plot.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <sstream>

namespace masse::scene
{
namespace
{
nlohmann::json distanceJson(const PositionDistance& d)
{
    return {{"rms", d.rms}, {"max", d.max}, {"mass", d.mass}};
}

/// The frame that ends at or after simulated time t (an event inside a frame is measured at its end).
std::optional<std::size_t> frameAt(const std::vector<Real>& times, Real t)
{
    const auto it = std::lower_bound(times.begin(), times.end(), t - 1e-9);
    if (it == times.end())
    {
        return std::nullopt;
    }
    return std::size_t(it - times.begin());
}

/// Every stage any of `runs` reached, in the order the first reached them, then the others'.
std::vector<std::pair<std::string, std::string>> stagesOf(const std::vector<const EngineResult*>& runs)
{
    std::vector<std::pair<std::string, std::string>> stages;
    for (const EngineResult* r : runs)
    {
        for (const StageEvent& e : r->events)
        {
            if (std::find(stages.begin(), stages.end(), std::make_pair(e.name, e.object)) == stages.end())
            {
                stages.emplace_back(e.name, e.object);
            }
        }
    }
    return stages;
}
} // namespace

nlohmann::json Comparison::report() const
{
    const SceneSpec& s = m_scene->spec();
    const LatticeSpec& lattice = s.sheet.lattice;
    nlohmann::json engines = nlohmann::json::array();
    const EngineResult& masse = m_results[0];
    for (std::size_t k = 0; k < m_results.size(); ++k)
    {
        const EngineResult& r = m_results[k];
        const TunnelCount tunnels = m_tunnels[k]->count();
        nlohmann::json events = nlohmann::json::array();
        for (const StageEvent& e : r.events)
        {
            events.push_back({{"name", e.name}, {"object", e.object}, {"sim_time", e.time}});
        }
        Real maxEnergy = 0;
        for (Real e : r.run.kineticEnergy)
        {
            maxEnergy = std::max(maxEnergy, e);
        }
        nlohmann::json engine = {
            {"key", r.key},
            {"label", r.label},
            {"engine", r.isBullet ? "bullet" : "masse"},
            {"settings", r.settings},
            {"events", events},
            {"penetration",
             {{"max", r.penetration.max()},
              {"mean", r.penetration.mean()},
              {"mean_when_penetrating", r.penetration.meanWhenPenetrating()},
              {"final_max", r.penetration.lastFrameMax()},
              {"penetrating_fraction", r.penetration.samples()
                                           ? Real(r.penetration.penetratingSamples()) / Real(r.penetration.samples())
                                           : Real(0)}}},
            {"tunnelled",
             {{"count", tunnels.tunnelled()},
              {"inside", tunnels.inside},
              {"beyond", tunnels.beyond},
              {"entered", tunnels.entered},
              {"started_inside", tunnels.startedInside}}},
            {"kinetic_energy",
             {{"final", r.run.kineticEnergy.empty() ? 0.0 : r.run.kineticEnergy.back()}, {"max", maxEnergy}}},
            {"frames", r.run.time.size()},
            {"simulated_seconds", r.run.simulatedSeconds()},
            {"wall_seconds", r.run.wallSeconds},
            {"wall_ms_per_simulated_second", r.run.wallMsPerSimulatedSecond()},
            {"failure", r.failure.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.failure)},
        };
        if (r.isBullet)
        {
            // Every stage either engine reached, with the distance between the two sheets when each reached it.
            const auto stages = stagesOf({&masse, &r});
            auto at = [&](std::optional<Real> t) -> nlohmann::json
            {
                if (!t)
                {
                    return nullptr;
                }
                const std::optional<std::size_t> frame = frameAt(m_times, *t);
                if (!frame || *frame >= r.distance.size())
                {
                    return nullptr;
                }
                return distanceJson(r.distance[*frame]);
            };
            nlohmann::json atEvents = nlohmann::json::array();
            for (const auto& [name, object] : stages)
            {
                const std::optional<Real> masseTime = masse.eventTime(name, object);
                const std::optional<Real> bulletTime = r.eventTime(name, object);
                atEvents.push_back({{"name", name},
                                    {"object", object},
                                    {"masse_time", masseTime ? nlohmann::json(*masseTime) : nlohmann::json(nullptr)},
                                    {"bullet_time", bulletTime ? nlohmann::json(*bulletTime) : nlohmann::json(nullptr)},
                                    {"at_masse_time", at(masseTime)},
                                    {"at_bullet_time", at(bulletTime)}});
            }
            engine["distance_to_masse"] = {
                {"final", r.distance.empty() ? nlohmann::json(nullptr) : distanceJson(r.distance.back())},
                {"final_time", r.run.time.empty() ? 0.0 : r.run.time.back()},
                {"events", atEvents}};
        }
        engines.push_back(engine);
    }
    nlohmann::json approximations = nlohmann::json::array();
    for (const Approximation& a : m_approximations)
    {
        approximations.push_back({{"subject", a.subject}, {"message", a.message}, {"runs", a.runs}});
    }
    return {
        {"scene", s.name},
        {"scene_file", s.path},
        {"structure", structureName(lattice.structure)},
        {"size",
         std::to_string(lattice.countX) + "x" + std::to_string(lattice.layers) + "x" + std::to_string(lattice.countZ)},
        {"masses", m_scene->system().massCount()},
        {"springs", m_scene->system().springCount()},
        {"dt", s.time.dt},
        {"frames", m_times.size()},
        {"sim_seconds", time()},
        {"contact_radius", s.contact.radius},
        {"units", {{"length", "m"}, {"time", "s"}, {"energy", "J"}, {"wall", "ms per simulated s"}}},
        {"measurement",
         {{"penetration", "every frame, for every mass of each engine: depth max(0, r - d) of its sphere of the "
                          "contact radius r, d the signed distance of its centre from the nearest obstacle surface "
                          "(BulletEnvironment::nearestSurface, negative inside); mean over all masses and frames"},
          {"tunnelled", "masses whose centre ended inside an obstacle or beyond one it entered (CompareMetrics.h)"},
          {"distance_to_masse", "RMS and maximum |x_i(Bullet) - x_i(MaSSE)| over corresponding masses, at the end "
                                "of the frame containing the event and at the last frame"},
          {"wall", "wall-clock time inside each engine's step, measurements excluded"}}},
        {"engines", engines},
        {"approximations", approximations},
        {"files",
         {{"series", "series.csv"},
          {"penetration_plot", "penetration.png"},
          {"kinetic_energy_plot", "kinetic_energy.png"},
          {"distance_plot", "distance.png"}}},
    };
}

std::string Comparison::table() const
{
    const SceneSpec& s = m_scene->spec();
    const int labelWidth = 38;
    // Columns as wide as the widest label (at least 26), so the table stays aligned.
    int columnWidth = 26;
    for (const EngineResult& r : m_results)
    {
        columnWidth = std::max(columnWidth, int(r.label.size()) + 2);
    }
    std::ostringstream out;
    auto row = [&](const std::string& name, const std::vector<std::string>& cells)
    {
        char head[128];
        std::snprintf(head, sizeof(head), "%-*s", labelWidth, name.c_str());
        out << head;
        for (const std::string& cell : cells)
        {
            char text[128];
            std::snprintf(text, sizeof(text), " %-*s", columnWidth - 1, cell.c_str());
            out << text;
        }
        out << '\n';
    };
    auto each = [&](const std::function<std::string(std::size_t)>& cell)
    {
        std::vector<std::string> cells;
        for (std::size_t k = 0; k < m_results.size(); ++k)
        {
            cells.push_back(cell(k));
        }
        return cells;
    };
    const LatticeSpec& lattice = s.sheet.lattice;
    out << "scene " << s.name << ": " << structureName(lattice.structure) << " " << lattice.countX << "x"
        << lattice.layers << "x" << lattice.countZ << ", " << m_scene->system().massCount() << " masses, "
        << m_scene->system().springCount() << " springs; dt = " << s.time.dt << " s; " << formatNumber("%.2f", time())
        << " s simulated (" << m_times.size() << " frames)\n\n";
    row("", each([&](std::size_t k) { return m_results[k].label; }));

    // Stage rows: every stage any engine reached, in the order MaSSE reached them, then the others'.
    std::vector<const EngineResult*> runs;
    for (const EngineResult& r : m_results)
    {
        runs.push_back(&r);
    }
    const auto stages = stagesOf(runs);
    for (const auto& stage : stages)
    {
        // Named copies, not structured bindings: C++20 lets a lambda capture a binding, but clang 14 refuses it.
        const std::string& name = stage.first;
        const std::string& object = stage.second;
        row(name == "rest" ? "rest (s)" : "first contact " + object + " (s)",
            each(
                [&](std::size_t k)
                {
                    const std::optional<Real> t = m_results[k].eventTime(name, object);
                    return t ? formatNumber("%.3f", *t) : std::string("-");
                }));
    }
    row("max penetration (mm)",
        each([&](std::size_t k) { return formatNumber("%.3g", 1000 * m_results[k].penetration.max()); }));
    row("mean penetration (mm)",
        each([&](std::size_t k) { return formatNumber("%.3g", 1000 * m_results[k].penetration.mean()); }));
    row("tunnelled nodes (inside/beyond)", each(
                                               [&](std::size_t k)
                                               {
                                                   const TunnelCount c = m_tunnels[k]->count();
                                                   return std::to_string(c.tunnelled()) + " (" +
                                                          std::to_string(c.inside) + "/" + std::to_string(c.beyond) +
                                                          "; entered " + std::to_string(c.entered) + ")";
                                               }));
    row("final kinetic energy (J)", each(
                                        [&](std::size_t k)
                                        {
                                            const auto& e = m_results[k].run.kineticEnergy;
                                            return e.empty() ? std::string("-") : formatNumber("%.3g", e.back());
                                        }));
    row("wall ms per simulated s",
        each([&](std::size_t k) { return formatNumber("%.1f", m_results[k].run.wallMsPerSimulatedSecond()); }));
    auto distanceCell = [&](std::size_t k, std::optional<std::size_t> frame)
    {
        const EngineResult& r = m_results[k];
        if (!r.isBullet || !frame || *frame >= r.distance.size())
        {
            return std::string("-");
        }
        const PositionDistance& d = r.distance[*frame];
        return formatNumber("%.1f", 1000 * d.rms) + " / " + formatNumber("%.1f", 1000 * d.max);
    };
    for (const auto& [name, object] : stages)
    {
        const std::optional<Real> t = m_results[0].eventTime(name, object);
        if (!t)
        {
            continue;
        }
        const std::optional<std::size_t> frame = frameAt(m_times, *t);
        row("to MaSSE at its " + (name == "rest" ? std::string("rest") : object) + " (mm rms/max)",
            each([&](std::size_t k) { return distanceCell(k, frame); }));
    }
    row("to MaSSE at the end (mm rms/max)",
        each([&](std::size_t k)
             { return distanceCell(k, m_times.empty() ? std::nullopt : std::optional(m_times.size() - 1)); }));
    for (const EngineResult& r : m_results)
    {
        if (!r.failure.empty())
        {
            out << r.label << " stopped: " << r.failure << '\n';
        }
    }
    return out.str();
}

std::string Comparison::seriesCsv() const
{
    std::ostringstream out;
    out << "time_s";
    for (const EngineResult& r : m_results)
    {
        out << ',' << r.key << "_penetration_mm," << r.key << "_kinetic_energy_J";
    }
    for (const EngineResult& r : m_results)
    {
        if (r.isBullet)
        {
            out << ',' << r.key << "_rms_distance_mm," << r.key << "_max_distance_mm";
        }
    }
    out << '\n';
    char text[64];
    for (std::size_t f = 0; f < m_times.size(); ++f)
    {
        std::snprintf(text, sizeof(text), "%.6f", m_times[f]);
        out << text;
        for (const EngineResult& r : m_results)
        {
            if (f < r.framePenetration.size())
            {
                std::snprintf(text, sizeof(text), ",%.6g,%.6g", 1000 * r.framePenetration[f], r.run.kineticEnergy[f]);
                out << text;
            }
            else
            {
                out << ",,"; // the engine had stopped
            }
        }
        for (const EngineResult& r : m_results)
        {
            if (!r.isBullet)
            {
                continue;
            }
            if (f < r.distance.size())
            {
                std::snprintf(text, sizeof(text), ",%.6g,%.6g", 1000 * r.distance[f].rms, 1000 * r.distance[f].max);
                out << text;
            }
            else
            {
                out << ",,";
            }
        }
        out << '\n';
    }
    return out.str();
}

void Comparison::writeOutputs(const std::string& directory) const
{
    std::filesystem::create_directories(directory);
    const std::string csv = directory + "/series.csv";
    writeFileAtomically(csv, seriesCsv());
    // gnuplot reads the CSV by column number: time is 1, engine k's penetration 2 + 2k and energy 3 + 2k, Bullet run
    // j's distances after all engines' columns.
    const std::string common = "set datafile separator ','\nset grid\nset key top right\n"
                               "set xlabel 'simulated time (s)'\n";
    const std::string title = m_scene->spec().name + ", dt = " + formatNumber(m_scene->spec().time.dt) + " s";
    // One curve per engine; `value` turns a column reference ("$3") into the plotted expression.
    auto curves = [&](int firstColumn, const std::function<std::string(const std::string&)>& value)
    {
        std::string plot = "plot ";
        for (std::size_t k = 0; k < m_results.size(); ++k)
        {
            std::string column = "$";
            column += std::to_string(firstColumn + 2 * int(k));
            plot += k ? ", '" : "'";
            plot +=
                csv + "' every ::1 using 1:(" + value(column) + ") with lines lw 2 title '" + m_results[k].label + "'";
        }
        return plot + "\n";
    };
    plotPng(common + "set title 'Deepest mass sphere in an obstacle each frame (" + title +
                "); both engines measured alike'\nset ylabel 'penetration (mm)'\n" +
                curves(2, [](const std::string& c) { return c; }),
            directory + "/penetration.png");
    // Kinetic energy spans orders of magnitude between the fall and rest: log scale, zeros left out.
    plotPng(common + "set title 'Kinetic energy (" + title +
                ")'\nset ylabel 'kinetic energy (J)'\nset logscale y\nset format y '%.0e'\n" +
                curves(3, [](const std::string& c) { return c + " > 0 ? " + c + " : 1/0"; }),
            directory + "/kinetic_energy.png");
    // A run's RMS (solid) and maximum (dashed) share its colour in the other two plots (gnuplot line type k + 1).
    std::string distance = common +
                           "set key outside right top\nset title 'Distance between corresponding masses, "
                           "Bullet to MaSSE (" +
                           title + ")'\nset ylabel 'distance (mm)'\nplot ";
    int column = 2 + 2 * int(m_results.size());
    for (std::size_t k = 1; k < m_results.size(); ++k)
    {
        const std::string colour = " lc " + std::to_string(k + 1);
        distance += k > 1 ? ", '" : "'";
        distance += csv + "' every ::1 using 1:" + std::to_string(column) + " with lines lw 2" + colour + " title '" +
                    m_results[k].label + " RMS', '' every ::1 using 1:" + std::to_string(column + 1) +
                    " with lines dt 2" + colour + " title '" + m_results[k].label + " max'";
        column += 2;
    }
    plotPng(distance + "\n", directory + "/distance.png");
    writeFileAtomically(directory + "/compare.json", report().dump(2) + "\n");
}
} // namespace masse::scene
