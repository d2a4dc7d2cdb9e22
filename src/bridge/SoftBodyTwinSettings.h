#pragma once
/// How the Bullet soft-body twin of a MaSSE sheet is set up (see SoftBodyTwin.h).
///
/// Bullet's classic soft body is position based: each substep of h seconds it predicts x += h v (gravity and forces
/// in v), finds node contacts, then runs `piterations` passes of contact and link projection, and sets
/// v = (x - x_old) / h * (1 - kDP). Its coefficients are therefore dimensionless fractions per pass or per substep,
/// not N/m or 1/s. Fields left unset (std::nullopt) are derived from the MaSSE sheet so the two engines describe the
/// same material. Nodes meet obstacles through the signed distance field of each shape (Bullet's SDF_RS), the one
/// mode that reports contact per node with the classic soft body.

#include "core/Types.h"

#include <optional>

namespace masse::bridge
{
struct SoftBodyTwinSettings
{
    /// Linear stiffness factor, dimensionless, range [0, 1] (0 excluded): the fraction of a link's length error one
    /// projection pass removes. Unset: every link gets the value whose static stretch under load equals its MaSSE
    /// spring's, from that spring's k_s, the reduced mass of its two masses, h and piterations
    /// (pbdLinearStiffness in StiffnessCalibration.h).
    std::optional<Real> kLST;
    /// Velocity damping factor per substep, dimensionless, range [0, 1): v is multiplied by 1 - kDP. Unset:
    /// 1 - exp(-c h), which is MaSSE's air drag f = -c m v over one substep.
    std::optional<Real> kDP;
    /// Dynamic friction factor against obstacles, dimensionless, range [0, 1]. Unset: MaSSE's mu for Coulomb
    /// friction (clamped to 1), 1 for sticky contact (approximated), 0 for frictionless. The twin gives every obstacle
    /// a Bullet friction of 1, so this is the whole coefficient.
    std::optional<Real> kDF;
    /// Hardness of contact with dynamic rigid bodies, dimensionless, range [0, 1], default 1 (Bullet's default). The
    /// twin's obstacles are all static or kinematic, so it only matters if that changes.
    Real kCHR = 1;
    /// Hardness of contact with static and kinematic obstacles, dimensionless, range [0, 1], default 1: the fraction
    /// of a node's depth below the margin that one pass removes. Bullet's own default is 0.1, with which a cloth at
    /// dt = 0.03 sinks through a static box; 1 is the fair baseline.
    Real kKHR = 1;
    /// Contact distance, m, range (0, 1]: a node is pushed back to this distance from an obstacle's surface. Unset:
    /// MaSSE's contact radius, so both engines keep mass centres equally far from surfaces. Bullet's default 0.25 m
    /// is never used.
    std::optional<Real> margin;
    /// Position-solver passes per substep, range [1, 1000], default 4. Bullet's default is 1; more passes make the
    /// contact and link projections converge (kLST is derived for the chosen count, so statics do not change).
    int piterations = 4;
    /// Bullet substeps per MaSSE step, range [1, 10000], default 1: h = dt / substeps (Bullet's fixedTimeStep).
    int substeps = 1;
    /// Cell size of Bullet's sparse signed-distance cache, m, range [0.001, 1], default 0.25 (Bullet's). Node contact
    /// distances are interpolated trilinearly between cell corners: exact next to a flat face, rounded near edges and
    /// corners by up to about a cell.
    Real sdfCellSize = 0.25;
};

/// Throws InputError naming the first field out of its range (field "kLST", "must be in (0, 1] (got 1.5)").
void validate(const SoftBodyTwinSettings& settings);
} // namespace masse::bridge
