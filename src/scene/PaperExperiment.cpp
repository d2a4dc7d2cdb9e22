#include "scene/PaperExperiment.h"

#include "scene/Scene.h"

#include "core/InputError.h"

#include <cstdio>
#include <sstream>

namespace masse::scene
{
std::vector<PaperRow> runPaperExperiment(const SceneSpec& base, const std::vector<int>& sizes,
                                         const std::function<void(const PaperRow&)>& onRow)
{
    if (base.obstacles.size() < 2)
    {
        throw InputError(base.path + ": the paper's experiment needs two obstacles (the first and second polyhedron)");
    }
    const std::string first = base.obstacles[0].name;
    const std::string second = base.obstacles[1].name;
    std::vector<PaperRow> rows;
    for (int n : sizes)
    {
        SceneSpec spec = base;
        spec.sheet.lattice.countX = n;
        spec.sheet.lattice.countZ = n;
        spec.sheet.sizeGiven = "--sizes";
        Scene scene(spec);
        while (!scene.finished())
        {
            scene.step();
        }
        PaperRow row;
        row.size = n;
        row.masses = scene.system().massCount();
        row.springs = scene.system().springCount();
        const std::pair<std::string, std::string> stages[] = {
            {"contact", first}, {"contact", second}, {"contact", "floor"}, {"rest", "sheet"}};
        Real previous = -1;
        row.inOrder = true;
        for (const auto& [name, object] : stages)
        {
            Real sim = -1;
            Real wall = -1;
            for (const SceneEvent& e : scene.events())
            {
                if (e.name == name && e.object == object)
                {
                    sim = e.simTime;
                    wall = e.wallTime;
                    break;
                }
            }
            row.inOrder = row.inOrder && sim >= 0 && sim >= previous;
            previous = sim;
            row.simTime.push_back(sim);
            row.wallTime.push_back(wall);
        }
        rows.push_back(row);
        if (onRow)
        {
            onRow(row);
        }
    }
    return rows;
}

std::string paperTable(const std::vector<PaperRow>& rows)
{
    std::ostringstream out;
    char line[256];
    std::snprintf(line, sizeof(line), "%-9s %6s %7s | %-29s | %-37s | %s\n", "sheet", "masses", "springs",
                  "simulated time to stage (s)", "wall-clock time to stage (ms)", "order");
    out << line;
    std::snprintf(line, sizeof(line), "%-9s %6s %7s | %6s %6s %6s %6s  | %8s %8s %8s %8s  |\n", "", "", "", "poly1",
                  "poly2", "floor", "rest", "poly1", "poly2", "floor", "rest");
    out << line;
    for (const PaperRow& r : rows)
    {
        std::snprintf(line, sizeof(line),
                      "%2dx2x%-3d %6zu %7zu | %6.2f %6.2f %6.2f %6.2f  | %8.1f %8.1f %8.1f %8.1f  | %s\n", r.size,
                      r.size, r.masses, r.springs, r.simTime[0], r.simTime[1], r.simTime[2], r.simTime[3],
                      1000 * r.wallTime[0], 1000 * r.wallTime[1], 1000 * r.wallTime[2], 1000 * r.wallTime[3],
                      r.inOrder ? "in order" : "OUT OF ORDER");
        out << line;
    }
    return out.str();
}

std::string paperCsv(const std::vector<PaperRow>& rows)
{
    std::ostringstream out;
    out << "size,masses,springs,sim_first_polyhedron_s,sim_second_polyhedron_s,sim_floor_s,sim_rest_s,"
           "wall_first_polyhedron_s,wall_second_polyhedron_s,wall_floor_s,wall_rest_s,in_order\n";
    for (const PaperRow& r : rows)
    {
        out << r.size << ',' << r.masses << ',' << r.springs;
        for (Real t : r.simTime)
        {
            out << ',' << t;
        }
        for (Real t : r.wallTime)
        {
            out << ',' << t;
        }
        out << ',' << (r.inOrder ? 1 : 0) << '\n';
    }
    return out.str();
}
} // namespace masse::scene
