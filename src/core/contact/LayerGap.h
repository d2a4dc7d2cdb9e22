#pragma once
/// Keeps a layered sheet's layers apart: each mass of an upper layer stays above the cell of masses beneath it (its
/// inter-layer neighbours in the layer below) by at least its rest height times the local thickness ratio h / h0.
///
/// Why: an upper mass sits over the middle of its cell, held by slanted inter-layer springs. Pressed toward the cell
/// (a vacuum draws the sheet onto a mould that has stopped the bottom layer; a plug pushes the top one), the springs'
/// push along the sheet's normal falls with the height, to nothing when the mass reaches the cell's plane: the
/// pyramid snaps through, and a hot sheet's springs creep the rest of the way. The layers then collapse onto the
/// mould, and the sheet loses the thickness that its layers stand for and the bending stiffness they give it. A real
/// sheet is nearly incompressible: it thins as it stretches (the thickness field, Thickness.h), its thickness carries
/// the pressure without giving way. So the floor is the rest height scaled by the thickness ratio: the layers come
/// together as the sheet thins, no closer.
///
/// Where: a scene has it on for forming (a pressure across the sheet, core/material/PressureLoad.h), where the load
/// presses the layers together against a mould. A free sheet's layers are left to their springs: a hot sheet
/// sagging under its own weight lets them come closer than h / h0 of the rest height as its springs creep, and
/// lifting them there puts energy into the sheet that nothing else does (a sagging sheet held at the floor diverges).
///
/// How: after every substep, a position-level constraint per upper mass (as a contact projection is), one-sided: the
/// height g over the cell's plane (its corners' centroid c, its normal n) must be at least g_min. A deficit d is
/// shared by inverse mass, as position-based dynamics does (the constraint's gradient is n for the upper mass and
/// -n / k for each of its k corners): lambda = d / (w_i + sum_j w_j / k^2), the upper mass moves by w_i lambda n and
/// each corner by -w_j lambda n / k; the approach velocity along n is removed in the same shares. Pinned masses and
/// masses touching an obstacle have w = 0: the mould holds what it touches, so the layer above is pushed off it
/// rather than the layer below into it, and a plug holds the upper layer it presses. An upper mass touching an
/// obstacle over a cell that touches one too has gone through its cell: it is the one that moves, alone; and so is one
/// that has gone through a cell only partly on an obstacle (draped over a mould's rim), whose free corners would
/// otherwise take the whole correction, several times the deficit, along a normal the rim may have tipped over. A cell
/// folded over a mould's rim (warped: its diagonals' midpoints apart along its normal) has no plane to stand over, so
/// the floor falls with the warp, to nothing at a warp of the rest height; and no correction moves a mass more than
/// eight floor heights, so that a tangled mass comes back over a few substeps rather than being thrown across the
/// mould. After a substep the approach velocity is removed; after the implicit solve, no more of it than the deficit /
/// h the solve itself can have closed (as position-based dynamics sets v = (x - x0) / h), so that a deficit older than
/// the solve is put right in position and not thrown into the velocity. The correction after the substep comes after
/// the obstacle projection, so a lower mass it pushes toward the mould (under an upper mass the plug holds) is kept
/// from going through it (ContactSolver::keepInFront).
///
/// Order and threads: every constraint is solved from the same positions (Jacobi), and each mass gathers its
/// corrections in a fixed order (its own constraint first, then those of the upper masses over it), so the result is
/// the same at any thread count and does not depend on which mass comes first. On the square lattices every sum over
/// a cell's corners or over the masses over a mass is taken in grid order and in pairs, and a cell's normal from its
/// diagonals, so that a mirror image gives the same numbers to the bit: a mirror-symmetric sheet stays exactly
/// mirror-symmetric.

#include "core/StepHook.h"
#include "core/lattice/Lattice.h"

#include <vector>

namespace masse
{
class ContactSolver;

class LayerGap final : public StepHook
{
public:
    explicit LayerGap(const Lattice& lattice);

    /// The obstacle contact, whose stuck masses an upper mass lifted off an obstacle is released from (nullptr: none).
    void setContactSolver(ContactSolver* contact) { m_contact = contact; }

    StageSet stages() const override { return {StepStage::AfterSolve, StepStage::AfterSubstep}; }
    /// With an implicit integrator, after its solve and before the obstacle contact's projection: a mass the solve
    /// carried through its cell is put back over it before the contact can take it for a touch of the mould (and
    /// hold it there, if the contact is sticky); the projection then puts back whatever the correction pushed into an
    /// obstacle.
    void afterImplicitSolve(MassSpringSystem& system, StepContext& context, Real h, Real time) override;
    /// After each substep and its contact: again with the touches the contact has just found, so that an upper mass
    /// the projection put on an obstacle through its own cell is lifted off it (and released, if it stuck).
    void afterSubstep(MassSpringSystem& system, StepContext& context, Real h, Real time) override;

    /// Masses moved by the last substep's correction.
    std::size_t lastCorrected() const { return m_lastCorrected; }
    /// Each upper mass's height over its cell divided by its rest height, for positions x (NaN for a mass of the
    /// bottom layer).
    std::vector<Real> heightRatios(const std::vector<Vec3>& x) const;

private:
    /// Removes each constraint's approach velocity; solveStep: the implicit solve's step h, after which no more of it
    /// than the deficit / h that the solve itself can have closed; 0 after a substep.
    void correct(MassSpringSystem& system, const StepContext& context, Real solveStep);
    /// The height of upper mass i over its cell and the cell's unit normal turned to the side i stands on at rest.
    Real height(const std::vector<Vec3>& x, Index i, Vec3& normal, Vec3& centroid) const;
    /// How far a square cell is from flat along its unit normal (0 for a triangle, always flat).
    Real warp(const std::vector<Vec3>& x, Index u, const Vec3& normal) const;

    std::vector<Index> m_upper;            ///< the masses with a cell beneath them, in mass order
    std::vector<std::size_t> m_cellOffset; ///< per upper mass: its cell's corners are m_cell[offset, next offset)
    std::vector<Index> m_cell;             ///< corners, in the lattice's spring order
    std::vector<Real> m_restHeight;        ///< m, per upper mass
    std::vector<Real> m_restSide;          ///< +1 or -1: the side of its cell's fan normal the mass stands on at rest
    std::vector<std::size_t> m_overOffset; ///< per mass: the upper masses whose cell holds it, m_over[offset, next)
    std::vector<std::uint32_t> m_over;     ///< positions in m_upper
    std::vector<Index> m_upperOf;          ///< per mass: its position in m_upper, or -1
    /// A square lattice's: each mass has four slots in m_over, the masses over it in grid order (or none), so that
    /// their corrections sum the same in a mirror image.
    bool m_squareSlots = false;

    // Per-substep state, per upper mass.
    std::vector<Real> m_positionShare; ///< lambda: the position correction's size, 0 when the floor holds
    std::vector<Real> m_velocityShare; ///< the approach velocity's correction
    std::vector<Vec3> m_normal;
    std::vector<std::uint8_t> m_upperYields; ///< moves back alone (see the file comment); its corners stay
    std::size_t m_lastCorrected = 0;
    ContactSolver* m_contact = nullptr;
};
} // namespace masse
