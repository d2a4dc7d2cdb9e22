#pragma once
/// Heat sources around a sheet: radiant heater panels and hot-air zones.
///
/// A heater is a flat rectangular panel radiating `power` watts from its front face as a diffuse (Lambertian)
/// emitter of uniform exitance P / A_panel. A small patch of sheet at x with outward normal n receives the
/// irradiance q = (P / A_panel) F, where F is the view factor from the patch to the panel,
///     F = (1 / 2 pi) sum over the panel's edges of  beta_k  n . g_k
/// (Lambert's contour formula: beta_k is the angle the edge subtends at x, g_k the unit normal of the plane through
/// x and the edge). This is the cos(theta_1) cos(theta_2) / (pi r^2) law integrated exactly over the panel, so it
/// falls with distance and angle as a point source far away and stays bounded (q <= P / A_panel) close up. The part
/// of the panel below the patch's own horizon is clipped off first; a patch behind the panel's plane gets nothing.
/// Shadows (by the sheet itself or obstacles) and reflections are not modelled.
///
/// A hot-air zone is an axis-aligned box of moving air at its own temperature: a sheet mass inside exchanges heat
/// with it through the zone's heat-transfer coefficient instead of with the still room air.

#include "core/Types.h"

#include <array>
#include <string>

namespace masse
{
struct RadiantHeater
{
    Vec3 centre = Vec3(0.3, 0.6, 0.3); ///< m, centre of the panel's face (default 0.2 m above Table 1's sheet)
    Vec3 normal = Vec3(0, -1, 0);      ///< direction the face looks (normalised when used); default down
    Vec3 widthAxis = Vec3::UnitX();    ///< direction of the width, made perpendicular to the normal when used
    Real width = 1.0;                  ///< m, > 0
    Real length = 1.0;                 ///< m, along normal x widthAxis, > 0
    Real power = 20000;                ///< W radiated from the face, >= 0 (20 kW/m^2 on the default 1 m^2 panel)
};

struct HotAirZone
{
    Vec3 minCorner = Vec3(-1, 0, -1); ///< m
    Vec3 maxCorner = Vec3(1, 1, 1);   ///< m, > minCorner on every axis
    Real temperature = 423.15;        ///< K (150 C), > 0
    Real heatTransfer = 50;           ///< W/(m^2 K), >= 0; forced air in an oven is some 20-100
};

/// Throw InputError naming the bad field (e.g. "power", "must be >= 0 W (got -5)").
void validate(const RadiantHeater& heater);
void validate(const HotAirZone& zone);

/// The panel's corners, counter-clockwise seen from in front of it.
std::array<Vec3, 4> heaterCorners(const RadiantHeater& heater);

/// View factor (0..1) from a small patch at x with unit outward normal n to the heater's face.
Real viewFactorToHeater(const RadiantHeater& heater, const Vec3& x, const Vec3& n);

/// Irradiance (W/m^2) the heater sends onto a patch at x with unit outward normal n.
Real heaterIrradiance(const RadiantHeater& heater, const Vec3& x, const Vec3& n);

inline bool contains(const HotAirZone& zone, const Vec3& x)
{
    return (x.array() >= zone.minCorner.array()).all() && (x.array() <= zone.maxCorner.array()).all();
}
} // namespace masse
