#pragma once
/// The linear system of one linearised implicit step, and its solve; shared by backward Euler and BDF2.
///
/// For an effective step a, a position offset d_i and a momentum term m_i per mass, it solves for the velocity change
///     (M - a D - a^2 K) dv = a f0 + a K (a v + d) + M m
/// (backward Euler: a = h, d = m = 0; BDF2: a = 2h/3, d = (x_n - x_n-1)/3, m = (v_n - v_n-1)/3), with K = df/dx and
/// D = df/dv. For a spring with unit direction n, length l and rest length s,
///     -K_aa = k n n^T + k max(0, 1 - s/l) (I - n n^T) + (2 k_r / l^3) n n^T [compressed only],  -D_aa = k_d n n^T,
/// and K_ab = -K_aa. The transverse term is clamped at zero for compressed springs (Choi and Ko 2002) and the
/// repulsion's transverse term is dropped, so the matrix stays symmetric positive definite and conjugate gradient
/// applies. Pinned masses get identity rows and a zero right-hand side, so dv = 0 there.
///
/// Velocity constraints from contact (see VelocityConstraint.h) are honoured with Baraff and Witkin's filter: with
/// S_i the projection onto a mass's free directions and c the prescribed change in the others, dv = S y + c where
///     (S A S + I - S) y = S (b - A c),
/// which keeps the matrix symmetric positive definite.
///
/// Speculative constraints (masses not touching their surface yet) make it an active set: the step is solved without
/// them, each one whose mass the step would carry through its surface is engaged (the mass arrives at the surface), and
/// the step solved again; an engaged one whose reaction pulls is released for good, and solved again. Each constraint
/// changes at most twice, and a frame without arrivals takes one solve. After maxSpeculativeRounds solves the last is
/// kept, and the contact's projection deals with what is left. Backward Euler and BDF2 both engage them.
///
/// The matrix is a SlotMatrix of 3x3 blocks, its pattern built once per topology; each step only rewrites values
/// through its slots, and every work array keeps its capacity, so a step allocates nothing once the first has run.

#include "core/StageObserver.h"
#include "core/integrate/ImplicitSpringTerms.h"
#include "core/integrate/Integrator.h"
#include "core/linear/CholeskyPreconditioner.h"
#include "core/linear/ConjugateGradient.h"
#include "core/linear/JacobiPreconditioner.h"
#include "core/linear/MultigridPreconditioner.h"
#include "core/linear/RefreshBudget.h"
#include "core/linear/SlotMatrix.h"

#include <array>
#include <cstdint>
#include <vector>

namespace masse
{
/// Where the integrator places a constrained mass, in its constrained directions, when they differ from x + d + a v'
/// (BDF2 puts it at x_start + h v' there, see Bdf2.cpp). The solve then uses, in those directions, the offset
/// that puts it there: d = (x_start - x) + (step - a) v', with v' the constraint's velocity. Without it the springs
/// of the solve would see the mass where it will not be, and the masses around a contact would be placed for a contact
/// that is not there (measured: the drop scene's sheet would keep sliding along the valley at 12 mm/s).
struct HeldPlacement
{
    Real step = 0; ///< 0: the constrained directions follow d + a v' like the others
    /// Per mass x_start - x, or empty for zero (the solve is about the step's start).
    const std::vector<Vec3>* fromStart = nullptr;
};

class ImplicitSolve
{
public:
    /// The most solves one step takes for its speculative constraints (an impact frame of a falling sheet takes 3).
    static constexpr int maxSpeculativeRounds = 6;
    /// The smallest residual scale, over the driving impulse (see residualScale).
    static constexpr Real equilibriumFloor = 1e-2;

    /// With `speculative`, speculative constraints are engaged where the step would carry their masses through
    /// their surfaces; without, they are never engaged (the contact's projection deals with those masses). With
    /// `coulombCap`, a resting constraint's friction damping is lowered, and the step solved again, where the friction
    /// impulse it gave exceeds mu times the constraint's normal reaction (see capFriction).
    /// With `releaseLifting`, a resting constraint whose reaction pulls the mass onto its surface is released for the
    /// step, and the step solved again (see releaseLifting).
    ImplicitSolve(const ImplicitSettings& settings, bool speculative, bool coulombCap = false,
                  bool releaseLifting = false)
        : m_settings(settings), m_speculative(speculative), m_coulombCap(coulombCap), m_releaseLifting(releaseLifting)
    {
    }

    /// Assembles and solves for dv with the forces already in system.particles.force, honouring `constraints`.
    /// `offset` and `momentum` are per mass, or empty for zero. Sets each constraint's reaction.
    IntegratorStats solve(MassSpringSystem& system, std::vector<VelocityConstraint>& constraints, Real a,
                          const std::vector<Vec3>& offset, const std::vector<Vec3>& momentum, HeldPlacement held = {});

    /// The velocity change of mass i from the last solve.
    Vec3 deltaV(Index i) const { return m_deltaV.segment<3>(Eigen::Index(3 * i)); }
    /// The largest velocity change of a mass in the last solve (m/s): how far a Newton iteration still moves.
    Real largestDeltaV() const;
    /// I - S of mass i in the last solve (the projection onto its constrained directions), zero if it had none.
    Mat3 held(Index i) const
    {
        return i < m_constraintOf.size() && m_constraintOf[i] >= 0
                   ? Mat3(Mat3::Identity() - m_filters[std::size_t(m_constraintOf[i])])
                   : Mat3(Mat3::Zero());
    }
    bool constrained() const { return !m_constrainedMasses.empty(); }
    /// Reports the solve's stages (Stage::SolverAnalysis to SolverIterations) to `observer`; nullptr for none.
    void setStageObserver(StageObserver* observer) { m_observer = observer; }

private:
    void buildPattern(const MassSpringSystem& system);
    /// The offset of this round: `offset`, with each honoured constraint's directions set as `held` says.
    const std::vector<Vec3>& heldOffset(const Particles& p, const std::vector<VelocityConstraint>& constraints, Real a,
                                        const std::vector<Vec3>& offset, HeldPlacement held);
    void assemble(const MassSpringSystem& system, Real a, const std::vector<Vec3>& offset,
                  const std::vector<Vec3>& momentum);
    bool applyConstraints(const MassSpringSystem& system, const std::vector<VelocityConstraint>& constraints, Real a);
    /// m_identityMasses for the matrix just assembled and filtered.
    void markIdentityMasses(const Particles& p);
    IntegratorStats runSolver();
    /// The impulse over a step a of the loads that drive the sheet: its weight, a |g| sqrt(sum m_i^2), or the loads
    /// applied to it, a sqrt(sum |f_i|^2), whichever is larger.
    static Real drivingImpulse(const MassSpringSystem& system, Real a);
    /// The scale the settings' tolerance applies to in a round whose right-hand side has norm `rhs`: |b|, at most
    /// `drivingImpulse` and at least equilibriumFloor times it (see the definition for why).
    static Real residualScale(Real rhs, Real drivingImpulse);
    void writeReactions(const MassSpringSystem& system, std::vector<VelocityConstraint>& constraints);
    /// Splits the reaction of a mass under two constraints between them (see the definition).
    void splitSharedReactions(std::vector<VelocityConstraint>& constraints);
    /// After a solve: engages each speculative constraint whose mass the step carries through its surface, releases
    /// each engaged one whose reaction pulls. Returns whether any changed (then the step is solved again).
    bool updateSpeculative(const MassSpringSystem& system, std::vector<VelocityConstraint>& constraints, Real a,
                           const std::vector<Vec3>& offset);
    /// After a solve: where a resting constraint's friction, a damping c sized at the frame's start for the slip
    /// expected then, gave an impulse a c |slip'| above mu times the normal reaction of this solve, lowers c to
    /// mu r_n / (a |slip'|). Returns whether any changed (then the step is solved again). Without it, a mass whose
    /// slip was expected to be small (at rest, say) is held by friction of any strength once the rest of the sheet
    /// pulls it: the damping is a regularised Coulomb law only at the slip it was sized for.
    bool capFriction(const MassSpringSystem& system, std::vector<VelocityConstraint>& constraints, Real a);
    /// After a solve: releases each resting constraint (one direction, not speculative) whose reaction pulls, so
    /// that its mass may leave the surface within the step. Returns whether any was released (then the step is
    /// solved again). A resting constraint is set up at the frame's start from the press of the frame before; without
    /// the release a mass the rest of the sheet lifts off in this step is held down for the whole step. With the
    /// release, the drop scene's sheet under BDF2 tips over the block's edge onto the wedge at 0.93-1.02 s, as the
    /// symplectic integrator's does (0.95-0.96 s).
    bool releaseLifting(std::vector<VelocityConstraint>& constraints);

    ImplicitSettings m_settings;
    StageObserver* m_observer = nullptr;
    bool m_speculative;
    bool m_coulombCap;
    bool m_releaseLifting;

    Real m_tolerance = 0; ///< of the current solve
    SlotMatrix<3> m_matrix;
    /// Each spring's part of the step's system (ImplicitSpringTerms.h), computed once and gathered by both its masses.
    std::vector<SpringTerm> m_springTerms;
    /// Per spring: false for one too short to have a direction, which adds nothing (its term means nothing).
    std::vector<std::uint8_t> m_springEngaged;
    /// What a spring does to its off-diagonal blocks, set with the pattern: the first spring joining two masses
    /// clears them, a later one joining the same two adds to them, one from a mass to itself has none.
    enum class OffDiagonal : std::uint8_t
    {
        First,
        Later,
        None
    };
    /// Per entry of the springs' adjacency (a spring seen from mass i), what mass i's gather needs besides the spring's
    /// term, laid out in the gather's order so that it reads them in sequence: where the spring's block sits in i's
    /// block column (the same place in each of its three columns), and how it is written.
    struct ColumnEntry
    {
        SparseMatrix::StorageIndex offset; ///< from the top of each of i's columns to the block's top entry
        OffDiagonal kind;
        bool first; ///< i is the spring's first end (it gives the spring's kv away, the second end takes it)
    };
    std::vector<ColumnEntry> m_columnEntries;
    Vector m_rhs;
    Vector m_deltaV;
    std::vector<Vec3> m_heldOffset; ///< heldOffset's result, kept between steps for its capacity
    ConjugateGradient m_cg;
    CholeskyPreconditioner m_cholesky;
    MultigridPreconditioner m_multigrid;
    JacobiPreconditioner m_jacobi;
    RefreshBudget m_refreshBudget; ///< when the preconditioner is refreshed (its fresh iterations for multigrid's rule)

    // Constraint filter of the current step; cleared, not freed, between steps.
    std::vector<int> m_constraintOf; ///< per mass: index into the arrays below, or -1
    /// Per mass, whether its rows of the filtered matrix are the identity's (pinned, or held in every direction); the
    /// conjugate gradient's product takes those rows as they are (ConjugateGradient::setIdentityMasses).
    std::vector<std::uint8_t> m_identityMasses;
    std::vector<Index> m_constrainedMasses;
    std::vector<Mat3> m_filters;                ///< S_i
    std::vector<std::uint8_t> m_heldEverywhere; ///< S_i is zero: the mass is held in all three directions
    std::vector<Vec3> m_prescribed;             ///< c_i, the velocity change in the constrained directions
    /// Orthonormal constrained directions per constrained mass.
    struct Basis
    {
        std::array<Vec3, 3> direction;
        /// The velocity each direction must have (its constraint's, given the directions before it).
        std::array<Real, 3> speed{};
        int count = 0;
        int constraints = 0; ///< honoured constraints on the mass
    };
    std::vector<Basis> m_bases;
    // The constrained rows as they were before filtering, to give each constraint its reaction after the solve.
    std::vector<Mat3> m_rowDiagonal;
    std::vector<Vec3> m_rowRhs;
    /// A spring with a constrained end, and its two off-diagonal blocks as the matrix held them before the filter:
    /// the constrained ends' reactions read them after the solve, and the right-hand side and the filter before it.
    struct ConstrainedSpring
    {
        std::uint32_t spring;
        Index a;
        Index b;
    };
    std::vector<ConstrainedSpring> m_constrainedSprings; ///< in increasing spring order
    std::vector<int> m_constrainedSpringOf;              ///< per spring: its index in m_constrainedSprings, or -1
    std::vector<Mat3> m_constrainedBlocks;               ///< per constrained spring, its blocks (a, b) and (b, a)
    bool m_sharedBlocks = false; ///< two springs join the same two masses (OffDiagonal::Later), sharing their blocks
    std::vector<Vec3> m_reaction;
    std::vector<int> m_firstConstraint; ///< per constrained mass, its first constraint (splitSharedReactions)
    bool m_sharedMass = false;          ///< some mass has two constraints this round (applyConstraints)

    const MassSpringSystem* m_patternSystem = nullptr;
    std::size_t m_patternMasses = 0;
    std::size_t m_patternSprings = 0;
};
} // namespace masse
