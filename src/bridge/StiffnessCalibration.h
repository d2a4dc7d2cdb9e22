#pragma once
/// From MaSSE's spring constants (N/m) to Bullet's dimensionless link stiffness kLST.
///
/// The formula. One Bullet link between nodes of reduced mass mu = 1 / (1/m_a + 1/m_b) (mu = m of the free node if
/// the other is pinned), under a steady force F along it. Each substep of h seconds, prediction adds F h^2 / mu to its
/// length error e, and each of the n projection passes removes the fraction kLST of the error (Bullet's PSolve_Links
/// to first order). At rest the error left after the passes is the error the step started with:
///
///     e = (e + F h^2 / mu) r,   r = (1 - kLST)^n    =>    F / e = mu (1 - r) / (h^2 r)
///
/// so the link stretches like a spring of k = mu ((1 - kLST)^-n - 1) / h^2, and a MaSSE spring of stiffness k is
/// matched by
///
///     kLST = 1 - (1 + k h^2 / mu)^(-1/n).
///
/// For the paper's Table 1 sheet (k = 90.2 and 60.8 N/m, 1 g masses, mu = 0.5 g) at h = 0.03 s, k h^2 / mu is 162
/// and 109, and kLST is 0.9939 and 0.9910 with n = 1, 0.7203 and 0.6915 with n = 4. kDP, damping and friction do not
/// enter: none changes a state at rest.
///
/// The check. In a lattice the passes sweep the links in order (Gauss-Seidel), so a link's error also moves when
/// its neighbours are projected, and a long chain of links converges much more slowly than one link; and the
/// derivation is first order in the substep's displacement g h^2 against the rest length. The formula holds while
/// k h^2 / mu is small (about 0.2 or less: the Table 1 sheet's sag then matches MaSSE's within 8%) and leaves the
/// twin far too soft when it is large. calibrateLinearStiffness measures instead: it settles the same sheet, held
/// by its pinned masses (for example clamped on two edges), in MaSSE (implicit Euler) and in the twin, and
/// bisects on one kLST for every link until the largest static sag is the same. When even rigid projection
/// (kLST = 1) sags more than MaSSE, it says so (reachable = false): Bullet cannot be that stiff at that substep
/// and iteration count. Measured figures are in tests/bridge/StiffnessCalibrationTest.cpp and the notes of the commit.

#include "SoftBodyTwinSettings.h"

#include "core/MassSpringSystem.h"
#include "core/lattice/Lattice.h"

namespace masse::bridge
{
/// kLST giving a link between masses of reduced mass `reducedMass` (kg), projected `iterations` times per substep
/// of `substep` seconds, the static stiffness `stiffness` (N/m). Returns a value in [0, 1).
Real pbdLinearStiffness(Real stiffness, Real reducedMass, Real substep, int iterations);
/// The inverse: the static stiffness (N/m) of a link of factor kLST in [0, 1).
Real pbdEquivalentStiffness(Real kLST, Real reducedMass, Real substep, int iterations);

/// How far a sheet sags under gravity with its pinned masses held, once settled.
struct StaticSag
{
    Real sag = 0;        ///< m, the largest drop of any mass below its starting height
    Index mass = 0;      ///< the mass that dropped most
    Real settleTime = 0; ///< s, simulated until the sag stopped changing
    bool settled = false;
};

/// Limits of a sag measurement: a run stops when the sag changed by less than `tolerance` (relative) over
/// `window` seconds, or after `maxTime` seconds (then settled is false).
struct SettleOptions
{
    Real window = 1.0;      ///< s
    Real tolerance = 1e-5;  ///< relative change of the sag over one window
    Real maxTime = 120.0;   ///< s
    Real airDamping = 10.0; ///< 1/s, drag used to settle quickly (it does not change the state at rest)
};

/// The sag in MaSSE: implicit Euler at dt, no obstacles.
StaticSag masseStaticSag(const MassSpringSystem& sheet, Real dt, const SettleOptions& options = {});
/// The sag of the sheet's Bullet twin with these settings at dt, no obstacles.
StaticSag twinStaticSag(const MassSpringSystem& sheet, Real dt, const SoftBodyTwinSettings& settings,
                        const SettleOptions& options = {});

struct StiffnessCalibration
{
    Real kLST = 0;       ///< the one factor for every link at which the twin sags as MaSSE does
    StaticSag masse;     ///< MaSSE's sag
    StaticSag bullet;    ///< the twin's sag at kLST
    int evaluations = 0; ///< twin runs made
    /// False when even kLST = 1 (rigid projection) sags more than MaSSE: Bullet cannot be that stiff at this
    /// substep and iteration count; kLST is then 1.
    bool reachable = true;
};

/// Pins the first and last mass of every row of the bottom layer: the sheet clamped on its two edges across x.
void clampOnTwoEdges(MassSpringSystem& sheet, const Lattice& lattice);

/// Bisects on a uniform kLST until the twin's static sag matches MaSSE's to `tolerance` (relative), at dt and with
/// the other settings given (substeps and piterations matter; kLST in `settings` is ignored). The sheet hangs from
/// its pinned masses (clampOnTwoEdges pins a lattice's edges); throws InputError if it has none.
StiffnessCalibration calibrateLinearStiffness(const MassSpringSystem& sheet, Real dt, SoftBodyTwinSettings settings,
                                              Real tolerance = 1e-3, const SettleOptions& options = {});
} // namespace masse::bridge
