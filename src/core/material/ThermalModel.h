#pragma once
/// Temperature of every mass of a sheet, advanced once per frame as a StepHook.
///
/// Each mass is a lump of the sheet's material: its layer's share of the thickness over the area it stands for at
/// rest, C_i = rho c_p (h0/L) A0_i, so the sheet's heat capacity is its material's whatever masses the mechanics
/// gives the lattice (the paper's 1 g per mass, say). Per frame of length dt it exchanges heat with
///  - the air, on each face of the sheet it lies on (the bottom layer's masses make the underside, the top layer's
///    the upper side, a single layer both): h (T_air - T_i) A_i, with the room air or, inside a hot-air zone, the
///    zone's air and coefficient;
///  - radiant heaters: absorptivity * q A_i on each face that looks at the panel (HeatSources.h);
///  - an obstacle it touches (StepContext::touchingObstacle): h_contact (T_obstacle - T_i) A_i;
///  - its neighbours, along springs, by conduction G_s (T_j - T_i).
/// A_i is the area the mass stands for in its layer now (SheetThickness), so a stretched region gains and loses heat
/// faster, and conduction follows the local thickness h.
///
/// Conductances (the cross-section given to each spring): the L layers share the thickness, each h/L.
///  - Planar springs: G = k (h/L) w, with w the cotangent weight of the layer's rest triangulation,
///    w = (cot alpha + cot beta)/2 over the angles facing the spring in its one or two triangles (squares are split
///    along the SLaMM diagonal). This is the finite-volume conductance of the edge: the cross-section is (h/L) times
///    the length of the dual (Voronoi) edge w L_s, l/sqrt(3) for an equilateral triangle's inner edge, the other
///    spacing for a grid edge. A linear temperature field is then steady on any planar lattice. Negative weights
///    (obtuse triangles) are clamped to 0 so the scheme keeps its maximum principle.
///  - Inter-layer springs: through the thickness, G = k a / (h/L), with a the upper layers' rest area shared equally
///    among all inter-layer springs and stretched with the sheet (times the local A / A0). Equal shares keep a
///    linear temperature field steady through the layers' edges, where shares of each upper mass's own area would
///    not (a tapered layer's edge masses stand for less area, and the imbalance acts as a false contact resistance).
///
/// Time integration is backward Euler, solved by conjugate gradient (the matrix C/dt + conductances + exchange
/// coefficients is symmetric, positive definite and an M-matrix): stable at any dt and free of overshoot, so the
/// sheet's 0.03 s frame needs no substeps however thin or finely meshed the sheet. It is first order in dt; heating
/// times are tens of seconds, so at 0.03 s the error is well below 0.1%. Masses can be held at a temperature
/// (clamps, test boundaries).

#include "core/StepHook.h"
#include "core/lattice/Lattice.h"
#include "core/linear/SlotMatrix.h"
#include "core/material/HeatSources.h"
#include "core/material/Material.h"
#include "core/material/Thickness.h"

#include <Eigen/IterativeLinearSolvers>

#include <span>
#include <vector>

namespace masse
{
struct ThermalSettings
{
    Real initialTemperature = 293.15; ///< K, every mass at the start (20 C); > 0
    Real airTemperature = 293.15;     ///< K, the room air; > 0
    /// W/(m^2 K), still air on each exposed face; natural convection is 5-25 (fold in radiation to the room here
    /// if wanted: about 6-10 more near 150 C); >= 0
    Real airHeatTransfer = 10;
    Real absorptivity = 0.9;        ///< fraction of heater radiation absorbed, [0, 1]; most plastics absorb 0.85-0.95
    Real contactHeatTransfer = 500; ///< W/(m^2 K) between a touching mass and an obstacle (plastic on metal); >= 0
    std::vector<RadiantHeater> heaters;
    std::vector<HotAirZone> hotAirZones; ///< a mass in several zones takes the first
    Real solverTolerance = 1e-10;        ///< relative residual of the conjugate gradient, (0, 1e-3]
    int maxIterations = 1000;            ///< per frame, >= 1
};

/// Throws InputError naming the bad field, heaters and zones included (e.g. "heaters[1].power", "must be >= 0 W").
void validate(const ThermalSettings& settings);

/// Heat flows of the last frame (W, into the sheet positive), and how the solve went.
struct ThermalReport
{
    Real heaterPower = 0;  ///< absorbed from heaters
    Real airPower = 0;     ///< from room air and hot-air zones
    Real contactPower = 0; ///< from obstacles
    int solverIterations = 0;
    Real solverResidual = 0;
};

class ThermalModel final : public StepHook
{
public:
    /// For a sheet built from `lattice` (same masses and springs, in the same order) of initial thickness h0 =
    /// `thickness`. Throws InputError for a bad material, thickness or settings.
    ThermalModel(const Lattice& lattice, const Material& material, Real thickness, const ThermalSettings& settings);

    /// Replaces the settings (heaters switched, zones moved...) after validating them.
    void setSettings(const ThermalSettings& settings);
    const ThermalSettings& settings() const { return m_settings; }
    /// Contact heat exchange: each obstacle's temperature (K), NaN for one at the air's temperature (it follows the
    /// air when that changes). Which mass touches which obstacle comes with each step (StepContext's
    /// touchingObstacle); obstacles beyond the end of the list exchange no heat.
    void setObstacleTemperatures(std::vector<Real> obstacleTemperature);
    const std::vector<Real>& obstacleTemperatures() const { return m_obstacleTemperature; }

    /// K, per mass. Writable for initial conditions; a held mass is reset to its held value every frame.
    std::vector<Real>& temperature() { return m_temperature; }
    const std::vector<Real>& temperature() const { return m_temperature; }
    /// Keeps a mass at a fixed temperature (K) until released.
    void holdTemperature(Index mass, Real temperature);
    void releaseTemperature(Index mass);

    /// One backward-Euler step of dt seconds at the system's current positions (endFrame calls it), with per mass
    /// the obstacle it touches or -1 (empty: no contact exchange).
    void advance(const MassSpringSystem& system, Real dt, std::span<const int> touchingObstacle = {});

    StageSet stages() const override { return {StepStage::BeginFrame, StepStage::EndFrame}; }
    /// Publishes the temperatures and the sheet's thickness in the step context for the hooks after it.
    void beginFrame(MassSpringSystem& system, StepContext& context, Real time, Real dt) override;
    void endFrame(MassSpringSystem& system, StepContext& context, Real time) override;

    const ThermalReport& lastReport() const { return m_report; }
    /// Areas, normals and thicknesses as of the last step; ViscoelasticSprings can share it (setThickness).
    SheetThickness& sheetThickness() { return m_geometry; }
    const SheetThickness& sheetThickness() const { return m_geometry; }
    /// Per spring, its conductance G_s (W/K) in the last step.
    const std::vector<Real>& conductance() const { return m_conductance; }

private:
    /// The air a mass at x exchanges heat with: a hot-air zone's, or the room's.
    struct AirAt
    {
        Real temperature;  ///< K
        Real heatTransfer; ///< W/(m^2 K)
    };

    void computeWeights(const Lattice& lattice);
    void buildPattern();
    void computeConductances();
    // The stages of advance(), in order.
    void requireSizes(const MassSpringSystem& system, std::span<const int> touchingObstacle) const;
    /// Each mass's capacity, air, heater and contact terms: the matrix diagonal and the right-hand side.
    void assembleExchanges(const std::vector<Vec3>& x, std::span<const int> touchingObstacle, Real dt);
    /// The springs' conduction; a held neighbour's coupling goes to the right-hand side.
    void assembleConduction();
    /// Held masses' rows become T = T_held; every mass's current temperature is the solve's first guess.
    void fixHeldTemperatures();
    void solve(Real dt);
    /// Takes the solution as the temperatures and sums the air and contact flows into the report.
    void reportFlows();
    AirAt airAt(const Vec3& x) const;
    /// W absorbed by mass i from every heater, on each of its exposed faces.
    Real absorbedHeat(std::size_t i, const Vec3& x, const Vec3& normal) const;

    Material m_material;
    ThermalSettings m_settings;
    SheetThickness m_geometry;
    std::vector<SpringEnds> m_ends;
    std::vector<SpringClass> m_class;
    std::vector<Real> m_weight;        ///< cotangent weight of planar springs
    Real m_interLayerArea = 0;         ///< m^2, a: rest area per inter-layer spring
    std::vector<Real> m_capacity;      ///< J/K
    std::vector<std::uint8_t> m_faces; ///< bit 0: bottom face exposed, bit 1: top face exposed
    std::vector<Real> m_temperature;
    std::vector<std::uint8_t> m_held;
    std::vector<Real> m_conductance;
    std::vector<Real> m_obstacleTemperature;
    Real m_frameDt = 0;
    ThermalReport m_report;
    // Per mass, scratch of one step: exchange coefficients (W/K) and their sources (W), flow = source - coeff * T.
    std::vector<Real> m_airCoefficient;
    std::vector<Real> m_airSource;
    std::vector<Real> m_contactCoefficient;
    std::vector<Real> m_contactSource;
    std::vector<Real> m_absorbed; ///< W from the heaters

    SlotMatrix<1> m_matrix; ///< C/dt + conductances + exchange coefficients, a scalar per mass and per spring end
    Eigen::VectorX<Real> m_rhs;
    Eigen::VectorX<Real> m_solution;
    Eigen::ConjugateGradient<SparseMatrix, Eigen::Lower | Eigen::Upper> m_solver;
};
} // namespace masse
