#pragma once
/// Sheet springs whose stiffness and flow follow temperature: the thermoplastic model of the sheet, as a StepHook.
///
/// Each spring is a Burgers element (BurgersSpring.h) with, from its temperature T (mean of its two masses) and its
/// stiffness per modulus g = k/E (MembraneStiffness.h):
///     k_M = g E(T),  c_M = 3 g eta(T),  k_K = kelvinModulusRatio k_M,  c_K = kelvinViscosityRatio c_M
/// The factor 3 is Trouton's: a Newtonian liquid of shear viscosity eta resists stretching with 3 eta, as an elastic
/// solid with Poisson's ratio 1/2 has E = 3 G; so the dashpot c relates to eta as the spring k relates to E.
///
/// The hook never touches the force kernel or the integrators: before every substep it writes each spring's
/// k_eff = 1/X and effective rest length L0 + u_0 (see BurgersSpring.h) into springs.stiffness() and
/// springs.restLength(), and after it reads the new lengths and advances the state (F, u, u_K). The spring's own
/// dashpot, springs.damping(), is kept at `dampingRatio` of critical for k_eff (the paper's sheet damping, 6%): a small
/// parallel damper that calms lattice vibrations and plays no part in the creep.
///
/// The force F is the state, not the elastic strain: when a spring cools, k_M rises a thousandfold and eta goes to
/// effectively infinite, but F is unchanged at unchanged length, so the shape a hot sheet took stays when it
/// cools (the rubbery strain is frozen in, as in a real sheet cooled under load) and only the small glassy strain
/// F/k_M springs back when the load goes. The permanent set u_D = u - u_K - F/k_M (burgersPermanentSet) grows by
/// that frozen strain on cooling.
///
/// Temperatures and thicknesses are read at the start of every frame (begin of Simulator::step); the substep h used to
/// build k_eff is the previous substep's (the frame length before the first). With the implicit integrator that is
/// always the substep actually taken. With an explicit one whose substep count changes between frames, the first
/// substep of such a frame applies a k_eff built for the old h; the state update always uses the h actually taken.
///
/// Wiring, as a scene does it (see ThermoplasticSheetTest's HeatedSheet):
///     Lattice lattice = buildLattice(spec);
///     ThermalModel thermal(lattice, material, thickness, thermalSettings);
///     MassSpringSystem sheet = makeMaterialSheet(lattice, material, thickness, thermalSettings.initialTemperature);
///     ... pin clamped masses ...
///     ViscoelasticSprings springs(sheet, stiffnessPerModulus(lattice, thickness), material, springSettings);
///     Simulator simulator(std::move(sheet), simulatorSettings);
///     simulator.setContactSolver(&contact);                    // optional
///     thermal.setObstacleTemperatures(obstacleTemperatures);   // optional
///     simulator.addHook(&thermal);
///     simulator.addHook(&springs);
/// The thermal model comes first: at the start of each frame it publishes its temperatures and the sheet's thickness
/// in the StepContext, where the springs read them (it steps at the end of a frame, so the springs see the
/// temperatures of the frame before). Without a heat model the springs keep their uniform temperature, and a
/// SheetThickness set as the context's `thickness` by its owner is followed all the same.

#include "core/StepHook.h"
#include "core/material/BurgersSpring.h"
#include "core/material/Material.h"
#include "core/material/Thickness.h"

#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace masse
{
enum class SpringModel
{
    Elastic, ///< k = g E(T) about the original rest length: stiffness follows temperature, nothing flows
    Maxwell, ///< spring k_M in series with dashpot c_M: instantaneous elasticity and viscous flow
    Burgers, ///< Maxwell plus a Kelvin-Voigt element: adds delayed (recoverable) elasticity
};

/// Parses "elastic", "maxwell" or "burgers"; throws InputError naming the allowed names.
SpringModel parseSpringModel(std::string_view name);
std::string_view springModelName(SpringModel model);
/// Every model's name, in the order messages list them: the scene reader's choice of `spring_model` takes them.
std::vector<std::string> springModelNames();

struct SpringModelSettings
{
    SpringModel model = SpringModel::Burgers;
    Real dampingRatio = 0.06; ///< fraction of critical damping of each spring's k_eff, in [0, 1]; paper Table 1: 6%
    /// Stiffness and viscosity scale with the local thickness h/h0 (a thinned region is weaker); needs the step
    /// context's thickness.
    bool followThickness = true;
    /// Stiffness and viscosity also scale with the local area stretch A/A0 = h0/h raised to this power (0: none): a
    /// strain-hardening sheet, whose thinned regions grow stiffer, so that stretch spreads to the thicker ones and a
    /// bubble blown from it thins more evenly, nearer what Crawford's cone law assumes (physics.md section 4). Needs
    /// the step context's thickness. In [0, maxStrainHardening].
    Real strainHardening = 0;
    Real initialTemperature = 293.15; ///< K, used while the step context carries no temperatures; > 0
};

/// The largest strainHardening accepted: at 4 a region thinned to half its thickness is 16 times as stiff.
inline constexpr Real maxStrainHardening = 4;

/// Throws InputError naming the bad field (dampingRatio outside [0, 1], a non-positive initialTemperature,
/// strainHardening outside [0, maxStrainHardening]).
void validate(const SpringModelSettings& settings);

class ViscoelasticSprings final : public StepHook
{
public:
    /// `system` is the sheet as built: its rest lengths are the springs' original ones. `stiffnessPerModulus` holds
    /// g = k/E for each spring (m), e.g. from stiffnessPerModulus(lattice, thickness). Throws InputError for a bad
    /// material, bad settings or a size mismatch.
    ViscoelasticSprings(const MassSpringSystem& system, std::vector<Real> stiffnessPerModulus, const Material& material,
                        const SpringModelSettings& settings);

    /// Temperature of every spring while the step context carries no per-mass temperatures (K).
    void setUniformTemperature(Real temperature);

    StageSet stages() const override { return {StepStage::BeginFrame, StepStage::AfterSubstep}; }
    /// Reads the context's temperatures (if any) and, with followThickness, updates its thickness (if any) from the
    /// positions; without one the springs keep the initial thickness.
    void beginFrame(MassSpringSystem& system, StepContext& context, Real time, Real dt) override;
    void afterSubstep(MassSpringSystem& system, StepContext& context, Real h, Real time) override;

    const Material& material() const { return m_material; }
    const SpringModelSettings& settings() const { return m_settings; }
    /// Per spring, as of the end of the last substep.
    const std::vector<BurgersState>& states() const { return m_state; }

private:
    void start(const MassSpringSystem& system, const StepContext& context);
    /// Recomputes the coefficients of springs whose temperature or thickness changed; returns whether any did.
    bool refreshParameters(const MassSpringSystem& system, std::span<const Real> temperature,
                           SheetThickness* thickness);
    /// Rebuilds the step coefficients for a substep of h and writes k_eff and damping into the system: of every
    /// spring, or with `changedChunksOnly` (h being the step they were built for) of the chunks whose parameters
    /// refreshParameters changed.
    void rebuildSteps(MassSpringSystem& system, Real h, bool changedChunksOnly);
    /// Writes the effective rest lengths for the next substep from the state.
    void writeRestLengths(MassSpringSystem& system);

    Material m_material;
    SpringModelSettings m_settings;
    std::vector<Real> m_perModulus;     ///< g = k/E, m
    std::vector<Real> m_originalLength; ///< L0, m
    std::vector<Real> m_reducedMass;    ///< kg, for the parallel damper
    std::vector<BurgersParams> m_params;
    std::vector<BurgersStep> m_step; ///< for m_stepLength
    std::vector<BurgersState> m_state;
    std::vector<Real> m_springTemperature;
    std::vector<Real> m_thicknessFactor; ///< per spring: what its thickness multiplies its stiffness and viscosity by
    std::vector<std::uint8_t> m_chunkChanged;  ///< per chunk of springs: a parameter changed (refreshParameters)
    std::vector<std::uint8_t> m_chunkFinite;   ///< per chunk of springs: every state finite after the substep
    std::vector<std::size_t> m_chunkBadSpring; ///< per chunk of springs: the first with a bad temperature, or none
    Real m_uniformTemperature;
    Real m_stepLength = 0; ///< h of m_step; 0 before the first frame
    bool m_started = false;
};
} // namespace masse
