/// `masse demo`: the main job. For now, the paper's TRiMM sheets (Table 2 sizes) fall from Table 1's position under
/// gravity with Table 1's parameters, and the table gives the time each takes to reach the floor's height.

#include "Commands.h"

#include "core/Damping.h"
#include "core/Lattice.h"
#include "core/Simulator.h"

#include <CLI/CLI.hpp>

#include <chrono>
#include <cstdio>
#include <limits>

namespace masse::app
{
namespace
{
constexpr Real paperFloorHeight = -2.81; // m, Table 1 room

void runDemo()
{
    std::printf("Paper Table 1 sheet (TRiMM, 90.2/60.8 N/m, 1 g masses, 3%% air, 6%% sheet damping), implicit Euler,\n"
                "dt = 0.03 s, falling from y = 0.3 m to the floor height y = %.2f m.\n\n",
                paperFloorHeight);
    std::printf("%-10s %7s %8s %16s %14s\n", "sheet", "masses", "springs", "sim time to floor", "wall ms");
    for (int n : {3, 6, 8, 9, 12})
    {
        LatticeSpec spec;
        spec.countX = n;
        spec.countZ = n;
        MassSpringSystem sheet = makeSheet(buildLattice(spec), SheetParams{});
        sheet.forces.airDamping = airDampingRate(paperAirRetention, paperTimeStep);
        Simulator simulator(std::move(sheet), SimulatorSettings{});
        const auto start = std::chrono::steady_clock::now();
        Real lowest = std::numeric_limits<Real>::infinity();
        while (simulator.time() < 10.0)
        {
            simulator.step(paperTimeStep);
            lowest = std::numeric_limits<Real>::infinity();
            for (const Vec3& x : simulator.system().particles.position)
            {
                lowest = std::min(lowest, x.y());
            }
            if (lowest <= paperFloorHeight)
            {
                break;
            }
        }
        const double wall = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
        std::printf("%2dx2x%-5d %7zu %8zu %14.2f s %14.1f\n", n, n, simulator.system().massCount(),
                    simulator.system().springCount(), simulator.time(), wall);
    }
}
} // namespace

void addDemoCommand(CLI::App& app)
{
    CLI::App* command = app.add_subcommand("demo", "The paper's TRiMM sheets falling under gravity (main job)");
    command->callback([] { runDemo(); });
}
} // namespace masse::app
