// Heat in a sheet: conduction to the analytic steady profile, cooling in air and on an obstacle against the lumped
// exponential, stability of the implicit step at the sheet's 0.03 s, energy balance, the heater's view factor
// against closed forms and quadrature, and which side of a sheet a heater warms first.

#include "support/TestSystems.h"

#include "core/InputError.h"
#include "core/lattice/Lattice.h"
#include "core/material/HeatSources.h"
#include "core/material/ThermalModel.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <limits>
#include <numbers>

using namespace masse;
using namespace masse::test;

namespace
{
constexpr Real pi = std::numbers::pi;

Lattice makeLattice(Structure structure, int nx, int layers, int nz, const Vec3& minCorner, const Vec3& maxCorner)
{
    LatticeSpec spec;
    spec.structure = structure;
    spec.countX = nx;
    spec.layers = layers;
    spec.countZ = nz;
    spec.minCorner = minCorner;
    spec.maxCorner = maxCorner;
    return buildLattice(spec);
}

/// Settings with no exchange at all: an insulated sheet.
ThermalSettings insulated(Real initial)
{
    ThermalSettings settings;
    settings.initialTemperature = initial;
    settings.airHeatTransfer = 0;
    settings.contactHeatTransfer = 0;
    return settings;
}

Real heatContent(const ThermalModel& model, const Lattice& lattice, const Material& m, Real thickness)
{
    // C_i = rho c (h0 / L) A0_i, as documented in ThermalModel.h.
    Real sum = 0;
    for (std::size_t i = 0; i < lattice.massCount(); ++i)
    {
        sum += m.density * m.specificHeat * thickness / lattice.spec.layers * model.sheetThickness().restArea()[i] *
               model.temperature()[i];
    }
    return sum;
}

/// Exact view factor from a patch to a parallel rectangle a x b whose corner lies straight above it at distance c.
Real cornerViewFactor(Real a, Real b, Real c)
{
    const Real x = a / c;
    const Real y = b / c;
    return (x / std::sqrt(1 + x * x) * std::atan(y / std::sqrt(1 + x * x)) +
            y / std::sqrt(1 + y * y) * std::atan(x / std::sqrt(1 + y * y))) /
           (2 * pi);
}
} // namespace

// A bar whose ends are held at 100 C and 20 C, insulated elsewhere, reaches the linear profile
// T(x) = T0 + (T1 - T0) (x - x0) / (x1 - x0) at every mass of every layer (1e-6 K), and carries Fourier's flux
// k t W (T0 - T1) / L through every cross-section (1e-6 relative): the conductances give the bar its true
// cross-section. A two-row square grid, and a four-row two-layer TRiMM strip whose rows, shifted half a spacing,
// end at different x: the end masses of every row of every layer are held at the profile's value there (left free,
// the zig-zag ends of the upper layer would be slanted insulated edges, which bend the profile by some mK even in a
// continuum). Backward Euler with 1e9 s steps
// reaches the steady state in a few steps.
TEST(Thermal, BarReachesTheLinearSteadyProfileAndFouriersFlux)
{
    const Material material;
    const Real thickness = 0.002;
    const Real hot = celsiusToKelvin(100);
    const Real cold = celsiusToKelvin(20);
    for (Structure structure : {Structure::Square2D, Structure::TRiMM})
    {
        const bool square = structure == Structure::Square2D;
        const Lattice lattice = square ? makeLattice(structure, 21, 1, 2, Vec3(0, 0, 0), Vec3(1, 0, 0.05))
                                       : makeLattice(structure, 21, 2, 4, Vec3(0, 0, 0), Vec3(1, 0.002, 0.1));
        const MassSpringSystem system = makeSheet(lattice, SheetParams{});
        ThermalSettings settings = insulated(cold);
        settings.solverTolerance = 1e-14; // a steady state to 1e-6 K needs a tight solve of a stiff system
        ThermalModel model(lattice, material, thickness, settings);
        const Real x0 = lattice.spec.minCorner.x();
        const Real x1 = lattice.spec.maxCorner.x();
        auto profile = [&](const Vec3& x) { return hot + (cold - hot) * (x.x() - x0) / (x1 - x0); };
        for (int layer = 0; layer < lattice.spec.layers; ++layer)
        {
            for (int row = 0; row < lattice.layerCountZ(layer); ++row)
            {
                const int last = lattice.layerCountX(layer) - 1;
                for (const Index end : {lattice.index(layer, row, 0), lattice.index(layer, row, last)})
                {
                    model.holdTemperature(end, profile(lattice.position[end]));
                }
            }
        }
        for (int i = 0; i < 5; ++i)
        {
            model.advance(system, 1e9);
        }
        for (std::size_t i = 0; i < lattice.massCount(); ++i)
        {
            EXPECT_NEAR(model.temperature()[i], profile(lattice.position[i]), 1e-6)
                << structureName(structure) << " mass " << i;
        }
        if (square)
        {
            // Flux through the cut between columns 9 and 10: the two row springs that cross it.
            Real flux = 0;
            for (std::size_t s = 0; s < lattice.springCount(); ++s)
            {
                const SpringEnds e = lattice.springs.ends()[s];
                const LatticeCoord a = lattice.coord[e.a];
                const LatticeCoord b = lattice.coord[e.b];
                if (std::min(a.column, b.column) == 9 && std::max(a.column, b.column) == 10)
                {
                    const Real direction = a.column < b.column ? 1 : -1;
                    flux += direction * model.conductance()[s] * (model.temperature()[e.a] - model.temperature()[e.b]);
                }
            }
            const Real width = lattice.spacingZ; // two rows one spacing apart: each edge stands for half of it
            const Real fourier = material.conductivity * thickness * width * (hot - cold) / (x1 - x0);
            EXPECT_NEAR(flux, fourier, 1e-6 * fourier);
        }
    }
}

// A sheet cooling in still air from 150 C: every mass follows Newton's law of cooling,
// T(t) = T_air + (T0 - T_air) exp(-2 h t / (rho c h0)) (both faces of a single layer), within 0.1% of the initial
// difference over 60 s of 0.03 s frames. The rate does not depend on the lattice's masses: heat capacity comes from
// the material.
TEST(Thermal, SheetInAirCoolsAsNewtonsLaw)
{
    const Material material;
    const Real thickness = 0.002;
    const Lattice lattice = makeLattice(Structure::Square2D, 8, 1, 8, Vec3(0, 0, 0), Vec3(0.5, 0, 0.5));
    Simulator simulator(makeSheet(lattice, SheetParams{}), SimulatorSettings{});
    for (std::size_t i = 0; i < lattice.massCount(); ++i)
    {
        simulator.system().particles.setPinned(Index(i), true);
    }
    ThermalSettings settings;
    settings.initialTemperature = celsiusToKelvin(150);
    settings.airTemperature = celsiusToKelvin(20);
    settings.airHeatTransfer = 10;
    ThermalModel model(lattice, material, thickness, settings);
    simulator.addHook(&model);
    const Real rate = 2 * settings.airHeatTransfer / (material.density * material.specificHeat * thickness);
    const Real difference = settings.initialTemperature - settings.airTemperature;
    Real worst = 0;
    simulate(simulator, 60.0, 0.03,
             [&](const Simulator& s)
             {
                 const Real expected = settings.airTemperature + difference * std::exp(-rate * s.time());
                 for (Real t : model.temperature())
                 {
                     worst = std::max(worst, std::abs(t - expected));
                 }
             });
    EXPECT_LT(worst, 0.001 * difference);
    EXPECT_LT(model.lastReport().airPower, 0);
}

// Backward Euler stays stable and overshoot-free at the sheet's 0.03 s even when conduction is far faster: a
// 0.1 mm sheet in four layers, whose through-thickness time constant (a few ms) is several times shorter than the
// step (explicit Euler would need dt below 2 / lambda_max; checked below to be under 0.03 s). The top layer starts at
// 150 C, the rest at 20 C, insulated. At every step the hottest temperature does not rise and the coldest does not
// fall (no overshoot) and the heat content is unchanged (1e-9 relative); after 1 s the temperatures agree with a run
// of 100 times smaller steps to within 1% of the initial difference.
TEST(Thermal, ImplicitStepIsStableAndMonotoneAtTheSheetsStep)
{
    const Material material;
    const Real thickness = 1e-4;
    const Lattice lattice = makeLattice(Structure::TRiMM, 6, 4, 6, Vec3(0, 0, 0), Vec3(0.2, 0.01, 0.2));
    const MassSpringSystem system = makeSheet(lattice, SheetParams{});
    const Real cold = celsiusToKelvin(20);
    const Real hot = celsiusToKelvin(150);
    ThermalModel model(lattice, material, thickness, insulated(cold));
    ThermalModel reference(lattice, material, thickness, insulated(cold));
    for (std::size_t i = lattice.layerStart[3]; i < lattice.massCount(); ++i)
    {
        model.temperature()[i] = hot;
        reference.temperature()[i] = hot;
    }
    const Real dt = 0.03;
    model.advance(system, 1e-12); // computes the conductances; the temperatures move by rounding at most
    // Gershgorin bound on the largest rate of the explicit scheme: max over masses of sum G / C.
    std::vector<Real> rowSum(lattice.massCount(), 0.0);
    for (std::size_t s = 0; s < lattice.springCount(); ++s)
    {
        rowSum[lattice.springs.ends()[s].a] += model.conductance()[s];
        rowSum[lattice.springs.ends()[s].b] += model.conductance()[s];
    }
    Real fastest = 0;
    for (std::size_t i = 0; i < lattice.massCount(); ++i)
    {
        const Real capacity =
            material.density * material.specificHeat * thickness / 4 * model.sheetThickness().restArea()[i];
        fastest = std::max(fastest, rowSum[i] / capacity);
    }
    ASSERT_GT(fastest * dt, 2.0) << "the test needs a step explicit Euler could not take";

    const Real initialHeat = heatContent(model, lattice, material, thickness);
    Real highest = hot;
    Real lowest = cold;
    for (int step = 0; step < 34; ++step)
    {
        model.advance(system, dt);
        for (int k = 0; k < 100; ++k)
        {
            reference.advance(system, dt / 100);
        }
        const auto [low, high] = std::minmax_element(model.temperature().begin(), model.temperature().end());
        EXPECT_LE(*high, highest + 1e-9);
        EXPECT_GE(*low, lowest - 1e-9);
        highest = *high;
        lowest = *low;
        EXPECT_NEAR(heatContent(model, lattice, material, thickness), initialHeat, 1e-9 * initialHeat);
    }
    EXPECT_LT(highest - lowest, 0.5 * (hot - cold)); // it did relax
    for (std::size_t i = 0; i < lattice.massCount(); ++i)
    {
        EXPECT_NEAR(model.temperature()[i], reference.temperature()[i], 0.01 * (hot - cold));
    }
}

// The heater's view factor against the exact one for a patch under the centre of a parallel rectangle (four corner
// rectangles, 1e-12), against the far-field point source A cos cos / (pi r^2) (0.1%), and against brute-force
// quadrature of cos theta1 cos theta2 / (pi r^2) over the panel for a tilted patch that sees part of the panel below
// its horizon (0.1%). Behind the panel: nothing.
TEST(Thermal, HeaterViewFactorMatchesClosedFormsAndQuadrature)
{
    RadiantHeater heater;
    heater.centre = Vec3(0, 1, 0);
    heater.normal = Vec3(0, -1, 0);
    heater.width = 0.6;
    heater.length = 0.4;
    heater.power = 1000;
    const Real distance = 0.25;
    const Vec3 below(0, 1 - distance, 0);
    EXPECT_NEAR(viewFactorToHeater(heater, below, Vec3::UnitY()), 4 * cornerViewFactor(0.3, 0.2, distance), 1e-12);
    EXPECT_NEAR(heaterIrradiance(heater, below, Vec3::UnitY()), 1000 / 0.24 * 4 * cornerViewFactor(0.3, 0.2, distance),
                1e-9);

    const Vec3 far(3, -29, 2);
    const Vec3 farNormal = Vec3(0.2, 1, -0.1).normalized();
    const Vec3 r = heater.centre - far;
    const Real pointSource =
        0.24 * (r.dot(farNormal) / r.norm()) * (r.dot(-heater.normal) / r.norm()) / (pi * r.squaredNorm());
    EXPECT_NEAR(viewFactorToHeater(heater, far, farNormal), pointSource, 1e-3 * pointSource);

    // A patch close below one edge, tilted so that its horizon cuts the panel.
    const Vec3 x(0.2, 0.8, 0.05);
    const Vec3 n = Vec3(-1, 0.5, 0).normalized();
    const int cells = 600;
    Real quadrature = 0;
    for (int i = 0; i < cells; ++i)
    {
        for (int j = 0; j < cells; ++j)
        {
            const Vec3 p(-0.3 + (i + 0.5) * 0.6 / cells, 1, -0.2 + (j + 0.5) * 0.4 / cells);
            const Vec3 d = p - x;
            const Real cosPatch = d.dot(n) / d.norm();
            const Real cosPanel = d.dot(-heater.normal) / d.norm();
            if (cosPatch > 0)
            {
                quadrature += cosPatch * cosPanel / (pi * d.squaredNorm()) * (0.6 / cells) * (0.4 / cells);
            }
        }
    }
    EXPECT_NEAR(viewFactorToHeater(heater, x, n), quadrature, 1e-3 * quadrature);
    EXPECT_GT(quadrature, 0.01);

    EXPECT_EQ(viewFactorToHeater(heater, Vec3(0, 1.2, 0), Vec3(0, -1, 0)), 0.0);
}

// A heater panel over one edge of a sheet warms that side first: after 5 s the masses within 0.3 m of the edge under
// it are on average hotter than those beyond 0.6 m, the hottest mass is on the near side, and the top layer (facing
// the heater) is hotter than the bottom one there. In the first frame, before conduction and losses matter, the
// top mass under the panel's centre gains absorptivity q A dt / C (1%).
TEST(Thermal, HeaterWarmsTheNearSideFirst)
{
    const Material material;
    const Real thickness = 0.002;
    LatticeSpec spec; // Table 1's sheet box
    spec.countX = 10;
    spec.countZ = 10;
    const Lattice lattice = buildLattice(spec);
    Simulator simulator(makeSheet(lattice, SheetParams{}), SimulatorSettings{});
    for (std::size_t i = 0; i < lattice.massCount(); ++i)
    {
        simulator.system().particles.setPinned(Index(i), true);
    }
    ThermalSettings settings;
    RadiantHeater heater;
    heater.centre = Vec3(-0.1, 0.6, 0.3);
    heater.normal = Vec3(0, -1, 0);
    heater.width = 0.3;
    heater.length = 1.0;
    heater.power = 6000;
    settings.heaters.push_back(heater);
    ThermalModel model(lattice, material, thickness, settings);
    simulator.addHook(&model);

    // The top-layer mass nearest below the panel's centre.
    Index probe = lattice.layerStart[1];
    for (Index i = lattice.layerStart[1]; i < lattice.massCount(); ++i)
    {
        const Vec3 d = lattice.position[i] - heater.centre;
        const Vec3 best = lattice.position[probe] - heater.centre;
        if (d.x() * d.x() + d.z() * d.z() < best.x() * best.x() + best.z() * best.z())
        {
            probe = i;
        }
    }
    const Real frame = 0.03;
    simulator.step(frame);
    const Real capacity =
        material.density * material.specificHeat * thickness / 2 * model.sheetThickness().restArea()[probe];
    const Real expectedRise = settings.absorptivity * heaterIrradiance(heater, lattice.position[probe], Vec3::UnitY()) *
                              model.sheetThickness().restArea()[probe] * frame / capacity;
    EXPECT_NEAR(model.temperature()[probe] - settings.initialTemperature, expectedRise, 0.01 * expectedRise);

    simulate(simulator, 5.0 - frame, frame, [](const Simulator&) {});
    Real near = 0;
    Real far = 0;
    int nearCount = 0;
    int farCount = 0;
    for (std::size_t i = 0; i < lattice.massCount(); ++i)
    {
        const Real fromEdge = lattice.position[i].x() - spec.minCorner.x();
        if (fromEdge < 0.3)
        {
            near += model.temperature()[i];
            ++nearCount;
        }
        else if (fromEdge > 0.6)
        {
            far += model.temperature()[i];
            ++farCount;
        }
    }
    EXPECT_GT(near / nearCount, far / farCount + 5.0);
    const auto hottest = std::max_element(model.temperature().begin(), model.temperature().end());
    EXPECT_LT(lattice.position[std::size_t(hottest - model.temperature().begin())].x() - spec.minCorner.x(), 0.3);
    const Index below = lattice.index(0, lattice.coord[probe].row, lattice.coord[probe].column);
    EXPECT_GT(model.temperature()[probe], model.temperature()[below]);
}

// An insulated sheet under a heater gains exactly the power it absorbs: sum C_i dT_i = sum over frames of the
// reported heater power times dt (1e-8 relative).
TEST(Thermal, InsulatedSheetGainsExactlyTheAbsorbedHeat)
{
    const Material material;
    const Real thickness = 0.002;
    LatticeSpec spec;
    spec.countX = 6;
    spec.countZ = 6;
    const Lattice lattice = buildLattice(spec);
    const MassSpringSystem system = makeSheet(lattice, SheetParams{});
    ThermalSettings settings = insulated(celsiusToKelvin(20));
    settings.heaters.push_back(RadiantHeater{});
    ThermalModel model(lattice, material, thickness, settings);
    const Real before = heatContent(model, lattice, material, thickness);
    Real absorbed = 0;
    for (int i = 0; i < 100; ++i)
    {
        model.advance(system, 0.03);
        absorbed += model.lastReport().heaterPower * 0.03;
    }
    EXPECT_GT(absorbed, 0);
    EXPECT_NEAR(heatContent(model, lattice, material, thickness) - before, absorbed, 1e-8 * absorbed);
}

// Hot air heats the masses inside its zone at the lumped rate 2 h_zone / (rho c h0) and leaves those outside at room
// temperature (apart from conduction near the boundary): a mass deep inside within 1%, one far outside within 0.1 K.
TEST(Thermal, HotAirZoneHeatsOnlyTheMassesInsideIt)
{
    const Material material;
    const Real thickness = 0.002;
    const Lattice lattice = makeLattice(Structure::Square2D, 21, 1, 5, Vec3(0, 0, 0), Vec3(1, 0, 0.2));
    const MassSpringSystem system = makeSheet(lattice, SheetParams{});
    ThermalSettings settings;
    settings.airHeatTransfer = 0;
    HotAirZone zone;
    zone.minCorner = Vec3(-1, -1, -1);
    zone.maxCorner = Vec3(0.5, 1, 1);
    zone.temperature = celsiusToKelvin(160);
    zone.heatTransfer = 40;
    settings.hotAirZones.push_back(zone);
    ThermalModel model(lattice, material, thickness, settings);
    const Real dt = 0.03;
    const int steps = 2000;
    for (int i = 0; i < steps; ++i)
    {
        model.advance(system, dt);
    }
    const Real rate = 2 * zone.heatTransfer / (material.density * material.specificHeat * thickness);
    const Real expected =
        zone.temperature + (settings.initialTemperature - zone.temperature) * std::exp(-rate * steps * dt);
    const Index inside = lattice.index(0, 2, 2);
    const Index outside = lattice.index(0, 2, 18);
    EXPECT_NEAR(model.temperature()[inside], expected, 0.01 * (expected - settings.initialTemperature));
    EXPECT_NEAR(model.temperature()[outside], settings.initialTemperature, 0.1);
}

// Masses touching a cold obstacle cool towards it at the rate h_contact / (rho c h0) (one face; 1%), masses
// touching an obstacle without a given temperature or touching nothing keep their heat (insulated otherwise). The
// thermal side of a cold mould freezing the sheet where it sticks.
TEST(Thermal, ContactWithAColdObstacleCoolsOnlyTheTouchingMasses)
{
    const Material material;
    const Real thickness = 0.002;
    const Lattice lattice = makeLattice(Structure::Square2D, 9, 1, 9, Vec3(0, 0, 0), Vec3(0.4, 0, 0.4));
    const MassSpringSystem system = makeSheet(lattice, SheetParams{});
    const Real hot = celsiusToKelvin(150);
    ThermalSettings settings = insulated(hot);
    settings.contactHeatTransfer = 500;
    ThermalModel model(lattice, material, thickness, settings);
    std::vector<int> touching(lattice.massCount(), 0); // all on obstacle 0 ...
    for (int row = 0; row < 9; ++row)
    {
        touching[lattice.index(0, row, 8)] = 1; // ... but the last column on obstacle 1, which has no temperature
    }
    const Real mould = celsiusToKelvin(40);
    model.setObstacleTemperatures({mould});
    const Real dt = 0.03;
    const int steps = 100;
    for (int i = 0; i < steps; ++i)
    {
        model.advance(system, dt, touching);
    }
    const Real rate = settings.contactHeatTransfer / (material.density * material.specificHeat * thickness);
    const Real expected = mould + (hot - mould) * std::exp(-rate * steps * dt);
    EXPECT_NEAR(model.temperature()[lattice.index(0, 4, 2)], expected, 0.01 * (hot - expected));
    EXPECT_LT(model.lastReport().contactPower, 0);
    // The column on obstacle 1 loses heat only by conduction to its cooled neighbours: slower by far.
    EXPECT_GT(model.temperature()[lattice.index(0, 4, 8)], expected + 0.5 * (hot - expected));

    EXPECT_NE(inputErrorOf([&] { model.setObstacleTemperatures({-400}); })
                  .find("obstacleTemperature[0]: must be above absolute zero"),
              std::string::npos);
}

// An obstacle given no temperature (NaN) is at the air's: a sheet lying on it relaxes towards the air temperature
// at the contact rate, T(t) = T_air + (T0 - T_air) exp(-H t / (rho c h0)), within 1% of the change, and follows the
// air when it changes (the room's walls and obstacles without "temperature_c" in a scene).
TEST(Thermal, ObstacleWithoutATemperatureIsAtTheAirs)
{
    const Material material;
    const Real thickness = 0.002;
    const Lattice lattice = makeLattice(Structure::Square2D, 5, 1, 5, Vec3(0, 0, 0), Vec3(0.2, 0, 0.2));
    const MassSpringSystem system = makeSheet(lattice, SheetParams{});
    const Real hot = celsiusToKelvin(150);
    ThermalSettings settings = insulated(hot); // no exchange with the air itself: only through the obstacle
    settings.airTemperature = celsiusToKelvin(60);
    settings.contactHeatTransfer = 500;
    ThermalModel model(lattice, material, thickness, settings);
    const std::vector<int> touching(lattice.massCount(), 0);
    model.setObstacleTemperatures({std::numeric_limits<Real>::quiet_NaN()});
    const Real dt = 0.03;
    const int steps = 100;
    const Real rate = settings.contactHeatTransfer / (material.density * material.specificHeat * thickness);
    auto expected = [&](Real air, Real start, int n) { return air + (start - air) * std::exp(-rate * n * dt); };
    for (int i = 0; i < steps; ++i)
    {
        model.advance(system, dt, touching);
    }
    const Real afterFirst = expected(settings.airTemperature, hot, steps);
    EXPECT_NEAR(model.temperature()[12], afterFirst, 0.01 * (hot - afterFirst));
    ASSERT_TRUE(std::isfinite(model.temperature()[12]));

    // The air cools to 0 C: the obstacle follows it.
    settings.airTemperature = celsiusToKelvin(0);
    model.setSettings(settings);
    const Real start = model.temperature()[12];
    for (int i = 0; i < steps; ++i)
    {
        model.advance(system, dt, touching);
    }
    const Real afterSecond = expected(settings.airTemperature, start, steps);
    EXPECT_NEAR(model.temperature()[12], afterSecond, 0.01 * (start - afterSecond));
}

// Bad settings are refused with the field named: a heater with negative power first of all.
TEST(Thermal, BadSettingsAreRefusedWithTheFieldNamed)
{
    const Material material;
    LatticeSpec spec;
    spec.countX = 3;
    spec.countZ = 3;
    const Lattice lattice = buildLattice(spec);

    ThermalSettings negativePower;
    negativePower.heaters.resize(2);
    negativePower.heaters[1].power = -5;
    EXPECT_EQ(inputErrorOf([&] { ThermalModel(lattice, material, 0.002, negativePower); }),
              "heaters[1].power: must be >= 0 W (got -5)");

    ThermalSettings flat;
    flat.heaters.resize(1);
    flat.heaters[0].width = 0;
    EXPECT_EQ(inputErrorOf([&] { validate(flat); }).rfind("heaters[0].width: ", 0), 0u);

    ThermalSettings absorbing;
    absorbing.absorptivity = 1.5;
    EXPECT_EQ(inputErrorOf([&] { validate(absorbing); }).rfind("absorptivity: ", 0), 0u);

    ThermalSettings inverted;
    inverted.hotAirZones.resize(1);
    inverted.hotAirZones[0].maxCorner = Vec3(-2, 1, 1);
    EXPECT_EQ(inputErrorOf([&] { validate(inverted); }).rfind("hotAirZones[0].maxCorner: ", 0), 0u);

    ThermalSettings convection;
    convection.airHeatTransfer = -1;
    EXPECT_EQ(inputErrorOf([&] { validate(convection); }).rfind("airHeatTransfer: ", 0), 0u);

    Material leaky;
    leaky.conductivity = -0.2;
    EXPECT_EQ(inputErrorOf([&] { ThermalModel(lattice, leaky, 0.002, ThermalSettings{}); }).rfind("conductivity: ", 0),
              0u);
    EXPECT_EQ(inputErrorOf([&] { ThermalModel(lattice, material, -0.002, ThermalSettings{}); }).rfind("thickness: ", 0),
              0u);
}
