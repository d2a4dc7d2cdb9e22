#pragma once
/// Pressure across the sheet (vacuum and pressure forming): a schedule of the pressure difference against time, and
/// the load it puts on the sheet's masses.
///
/// Sign convention: p = (pressure above the sheet) - (pressure below it), "above" being the side its top layer faces
/// (+y at rest). p > 0 pushes the sheet toward its underside: air pressure over the sheet, or a vacuum drawn under
/// it, presses it down into a female mould below. p < 0 blows it up (a free bubble rising off the clamp).
///
/// The load acts on every layer's surface (LatticeSurface.h): each layer stands for 1/L of the sheet's thickness
/// (MembraneStiffness.h), so each takes 1/L of the pressure. Each triangle takes (p/L) times its vector area, -p A n /
/// L, split equally among its three corners (the consistent load of a uniform pressure on a linear triangle), so a
/// mass gets its layer's part of p times its share of the deformed surface's area along the surface normal (a square
/// lattice's square is taken as both of its splits into two triangles at half weight, a quarter to each corner of a
/// flat square, so that the load is as symmetric as the lattice). Layers
/// loaded alike deform alike, so the inter-layer springs carry no share of the load across the sheet.
///
/// Sealing: where the sheet has closed onto the mould, the mould carries the pressure. A bottom-layer mass that
/// touched an obstacle in the last frame is sealed, and so is a mass of a higher layer whose inter-layer neighbours
/// below are all sealed; a triangle whose three corners are sealed gets no load (the air under it is gone and the
/// mould's reaction balances the air above; the trapped-air model, where a closed pocket under the sheet keeps its
/// own pressure, is not modelled). A triangle still partly free carries the full difference.
///
/// Time: the load is recomputed from the positions at the start of every frame and after every substep, with the
/// pressure at the end of the substep to come. The implicit integrator takes one substep per frame, so inside its
/// solve the load is that of the frame's start: it lags the geometry by one step. The load's own stiffness (a
/// follower load turns with the surface) is left out of the implicit matrix; it is small beside the membrane's
/// (p against E t / l), and PressureLoad.LaggedLoadIsStableAtLargeSteps checks that the lag does not destabilise a
/// bubble at large steps.

#include "core/StepHook.h"
#include "core/lattice/LatticeSurface.h"

#include <cstdint>
#include <vector>

namespace masse
{
/// One key of a pressure schedule.
struct PressureKey
{
    Real time = 0;     ///< s
    Real pressure = 0; ///< Pa, above minus below (see the sign convention above)
};

/// Piecewise-linear pressure against time; constant before the first key and after the last; zero with no keys.
class PressureSchedule
{
public:
    PressureSchedule() = default;
    /// Throws InputError naming the key's field ("keys[2].time") when times do not increase or a value is not finite.
    explicit PressureSchedule(std::vector<PressureKey> keys);
    Real at(Real time) const;
    const std::vector<PressureKey>& keys() const { return m_keys; }
    bool empty() const { return m_keys.empty(); }

private:
    std::vector<PressureKey> m_keys;
};

class PressureLoad final : public StepHook
{
public:
    PressureLoad(const Lattice& lattice, PressureSchedule schedule);

    /// Whether the sheet seals where it touches: at the end of every frame the step context's touchingObstacle (per
    /// mass, the obstacle it touched or -1) decides which triangles are sealed (see above). Off: nothing is sealed.
    void setSealing(bool sealing) { m_sealing = sealing; }

    StageSet stages() const override { return {StepStage::BeginFrame, StepStage::AfterSubstep, StepStage::EndFrame}; }
    void beginFrame(MassSpringSystem& system, StepContext& context, Real time, Real dt) override;
    void afterSubstep(MassSpringSystem& system, StepContext& context, Real h, Real time) override;
    void endFrame(MassSpringSystem& system, StepContext& context, Real time) override;
    bool writesExternalForcesMidFrame() const override { return true; }

    /// Writes the load for positions x and pressure p into `force` (one per mass), leaving out the triangles sealed
    /// as of the last frame.
    void computeLoad(const std::vector<Vec3>& x, Real pressure, std::vector<Vec3>& force) const;

    const PressureSchedule& schedule() const { return m_schedule; }
    /// Replaces the schedule between frames (a script's or the viewer's "pressure" action); the load follows it from
    /// the next frame.
    void setSchedule(PressureSchedule schedule) { m_schedule = std::move(schedule); }
    /// Pa, the pressure of the load now applied.
    Real currentPressure() const { return m_pressure; }
    /// N per mass, the load now applied (part of Particles::externalForce).
    const std::vector<Vec3>& load() const { return m_applied; }
    /// m^2, the area of the bottom layer's surface sealed onto an obstacle at the last load.
    Real sealedArea() const { return m_sealedArea; }

private:
    /// Replaces the load this hook put into externalForce with the one for the current positions and `pressure`.
    void apply(MassSpringSystem& system, Real pressure);

    PressureSchedule m_schedule;
    int m_layers = 1;
    std::vector<Triangle> m_triangles;       ///< every layer's, bottom first
    std::vector<Real> m_triangleShare;       ///< per triangle: 1 / L (a square lattice's: 1 / 2L, see the constructor)
    std::vector<std::uint8_t> m_bottom;      ///< per triangle: of the bottom layer
    std::vector<std::vector<Index>> m_below; ///< per mass: its inter-layer neighbours in the layer below
    bool m_sealing = false;
    std::vector<std::uint8_t> m_sealed; ///< per mass: touched an obstacle in the last frame
    std::vector<Vec3> m_applied;
    std::vector<Vec3> m_next;
    Real m_pressure = 0;
    mutable Real m_sealedArea = 0;
    std::vector<std::size_t> m_cornerOffsets;     ///< mass i's triangles: m_cornerTriangles[offsets[i], offsets[i + 1])
    std::vector<std::uint32_t> m_cornerTriangles; ///< per mass, the triangles it is a corner of, in increasing order
    mutable std::vector<Vec3> m_share;            ///< computeLoad's work: per triangle, its load on each corner
    mutable std::vector<Real> m_sealedPart;       ///< per triangle: its sealed area (bottom layer), 0, or -1 if loaded
};
} // namespace masse
