#pragma once
/// Time integrators. The three explicit ones are conditionally stable and are substepped by the Simulator from a
/// stability estimate; implicit Euler, BDF2 and TR-BDF2 are stable at any step.

#include "core/MassSpringSystem.h"
#include "core/StageObserver.h"
#include "core/StepContext.h"
#include "core/StepStage.h"

#include <memory>
#include <span>
#include <string>
#include <string_view>

namespace masse
{
enum class IntegratorKind
{
    ExplicitEuler,   ///< the paper's: x += h v, v += h a (both from the old state); needs damping to be stable
    SymplecticEuler, ///< v += h a, x += h v (new velocity); conserves energy on average
    VelocityVerlet,  ///< second order; forces re-evaluated at the new positions
    ImplicitEuler,   ///< backward Euler, linearised (Baraff and Witkin 1998), solved by conjugate gradient
    Bdf2,            ///< second-order backward differentiation, linearised (Choi and Ko 2002); little numerical damping
    TrBdf2, ///< trapezoidal rule then BDF2 in each step (TR-BDF2), BDF2 steps in contact; keeps slow motion best
};

class Integrator;
struct ImplicitSettings;

/// One registered integrator: its kind, the name scene files and flags take, and how to make it. The names the scene
/// reader takes, the viewer's menu, the help strings and the memory estimate all read the registry.
struct IntegratorEntry
{
    IntegratorKind kind;
    std::string_view name; ///< in scene files and flags
    bool explicitStep;     ///< conditionally stable: substepped from the stability estimate
    int solvesKept;        ///< implicit solves (matrix and preconditioner) held at once, for the memory estimate
    std::unique_ptr<Integrator> (*make)(const ImplicitSettings& implicit);
};

// Each integrator's factory, defined in its own file; the explicit ones take the implicit settings and ignore them,
// so that every entry makes its integrator the same way.
std::unique_ptr<Integrator> makeExplicitEuler(const ImplicitSettings& settings);
std::unique_ptr<Integrator> makeSymplecticEuler(const ImplicitSettings& settings);
std::unique_ptr<Integrator> makeVelocityVerlet(const ImplicitSettings& settings);
std::unique_ptr<Integrator> makeImplicitEuler(const ImplicitSettings& settings);
std::unique_ptr<Integrator> makeBdf2(const ImplicitSettings& settings);
std::unique_ptr<Integrator> makeTrBdf2(const ImplicitSettings& settings);

/// The registry of integrators, one entry each in the order menus and help list them. It sits beside IntegratorKind
/// so that an integrator is its own file in this folder (which src/core/CMakeLists.txt globs), its value, factory and
/// entry here, and its name in data/scenes/README.md's `integrator` table. TR-BDF2 keeps a solve (matrix and factor)
/// for each of its two stages; BDF2 one, for its steps with contact too.
inline constexpr IntegratorEntry integratorTable[] = {
    {IntegratorKind::ExplicitEuler, "euler", true, 0, makeExplicitEuler},
    {IntegratorKind::SymplecticEuler, "symplectic", true, 0, makeSymplecticEuler},
    {IntegratorKind::VelocityVerlet, "verlet", true, 0, makeVelocityVerlet},
    {IntegratorKind::ImplicitEuler, "implicit", false, 1, makeImplicitEuler},
    {IntegratorKind::Bdf2, "bdf2", false, 1, makeBdf2},
    {IntegratorKind::TrBdf2, "trbdf2", false, 2, makeTrBdf2},
};

std::span<const IntegratorEntry> integrators();
/// "euler, symplectic, verlet, implicit, bdf2 or trbdf2", from the registry, for help strings.
std::string integratorNameList();

/// Parses a registered name (any case); throws InputError naming the allowed names.
IntegratorKind parseIntegrator(std::string_view name);
std::string_view integratorName(IntegratorKind kind);
bool isExplicit(IntegratorKind kind);
/// Implicit solves an integrator holds at once (0 for the explicit ones).
int solvesKept(IntegratorKind kind);

/// The implicit solver's preconditioner (see MultigridPreconditioner.h, and docs/model.md for when each suits).
enum class PreconditionerKind
{
    Multigrid, ///< an aggregation multigrid V-cycle built from a recent matrix, rebuilt only when it has drifted
    Cholesky,  ///< a sparse LDL^T factor of a recent matrix, refactored only when it has drifted
    Jacobi,    ///< the diagonal; iterations grow with size and stiffness
};

/// "multigrid", "cholesky" or "jacobi".
std::string_view preconditionerName(PreconditionerKind kind);
/// Parses a preconditioner's name; throws InputError naming the allowed names.
PreconditionerKind parsePreconditioner(std::string_view name);

/// Settings of the implicit solver.
struct ImplicitSettings
{
    /// The conjugate gradient's residual, at most this times a scale: the right-hand side's norm, kept between a
    /// hundredth of and the whole impulse over the step of the loads that drive the sheet (its weight, or its applied
    /// loads where they are larger; ImplicitSolve::residualScale). 1e-5: the physics tests agree with 1e-7 at a third
    /// of the iterations.
    Real tolerance = 1e-5;
    int maxIterations = 1000; ///< per step
    PreconditionerKind preconditioner = PreconditionerKind::Cholesky;
    /// Iterations the old factor always gets before it is refactored from the current matrix (the solve then
    /// finishes in one or two more); beyond that it keeps its factor while the iterations it takes beyond a fresh
    /// factor's, summed since the last refactorisation, cost less than one (RefreshBudget). Ten iterations let
    /// a factor that has drifted a little finish its solve where a refactorisation for it would cost more.
    int refreshAfterIterations = 10;
    /// The same for the multigrid hierarchy: it is rebuilt after this many iterations, or after half this many beyond
    /// what it took fresh if that is more (a fresh cycle takes several).
    int multigridRefreshAfterIterations = 8;
};

/// What one step of an integrator reports.
struct IntegratorStats
{
    int solverIterations = 0; ///< conjugate-gradient iterations (implicit only)
    /// Residual reached, over the scale the tolerance applies to (implicit only; see ImplicitSettings::tolerance)
    Real solverResidual = 0;
    bool hitIterationCap = false; ///< the solve stopped at maxIterations short of the tolerance
    int refactorisations = 0;     ///< preconditioner rebuilds (implicit with a refreshed preconditioner only)

    /// Counts a later solve of the same step in: its iterations and rebuilds added, its residual the step's.
    void add(const IntegratorStats& later)
    {
        solverIterations += later.solverIterations;
        solverResidual = later.solverResidual;
        hitIterationCap = hitIterationCap || later.hitIterationCap;
        refactorisations += later.refactorisations;
    }
};

class Integrator
{
public:
    virtual ~Integrator() = default;
    /// Advances the system by one step of h seconds, with the frame's velocity constraints in `context` (the
    /// integrators whose honoursConstraints() is true honour them and write their reactions; the others ignore it)
    /// and what the step may skip (`hints`: only the symplectic pass reads them).
    virtual IntegratorStats step(MassSpringSystem& system, StepContext& context, Real h, const SubstepHints& hints) = 0;
    /// A step that skips nothing.
    IntegratorStats step(MassSpringSystem& system, StepContext& context, Real h)
    {
        return step(system, context, h, SubstepHints{});
    }
    /// A step without constraints.
    IntegratorStats step(MassSpringSystem& system, Real h)
    {
        StepContext none;
        return step(system, none, h);
    }
    virtual IntegratorKind kind() const = 0;
    /// Reports the implicit solve's stages (StageObserver.h) to `observer`, or to none with nullptr; the explicit
    /// integrators have none.
    virtual void setStageObserver(StageObserver* /*observer*/) {}
    /// Whether the step honours the context's constraints (otherwise the contact solver's projection does all).
    virtual bool honoursConstraints() const { return false; }
};

std::unique_ptr<Integrator> makeIntegrator(IntegratorKind kind, const ImplicitSettings& implicit = {});
} // namespace masse
