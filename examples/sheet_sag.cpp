// Embedding MaSSE: a Table 1 TRiMM sheet (9x2x9, 1 m square) clamped along its two x edges sags under its weight.
#include "core/MassSpringSystem.h"
#include "core/Simulator.h"
#include "core/forces/Damping.h"
#include "core/lattice/Lattice.h"

#include <cstdio>

int main()
{
    masse::LatticeSpec spec; // Table 1: TRiMM, the sheet box x -0.2..0.8, z -0.2..0.8 m
    spec.countX = spec.countZ = 9;
    const masse::Lattice lattice = masse::buildLattice(spec);
    masse::MassSpringSystem sheet = masse::makeSheet(lattice, masse::SheetParams{}); // 1 g masses, 90 N/m springs
    sheet.forces.airDamping = masse::airDampingRate(masse::paperAirRetention, 0.03);
    for (masse::Index i = 0; i < masse::Index(lattice.massCount()); ++i)
    {
        const masse::LatticeCoord& c = lattice.coord[std::size_t(i)];
        if (c.layer == 0 && (c.column == 0 || c.column == spec.countX - 1))
        {
            sheet.particles.setPinned(i, true); // the clamped edges
        }
    }
    const masse::Index middle = lattice.index(0, spec.countZ / 2, spec.countX / 2);
    masse::Simulator simulator(std::move(sheet), masse::SimulatorSettings{masse::IntegratorKind::SymplecticEuler});
    for (int step = 0; step < 400; ++step) // 12 s at the paper's 0.03 s step
    {
        simulator.step(0.03);
    }
    const double sag = lattice.position[std::size_t(middle)].y() - simulator.system().particles.position[middle].y();
    std::printf("sag of the middle after %.2f s: %.17g m\n", simulator.time(), sag);
}
