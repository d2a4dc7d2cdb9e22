#include "core/material/HeatSources.h"
#include "core/Format.h"

#include "core/InputError.h"

#include <Eigen/Geometry>

#include <cmath>
#include <numbers>
#include <sstream>
#include <vector>

namespace masse
{
namespace
{
/// Unit normal and unit width and length directions of the panel.
struct PanelFrame
{
    Vec3 normal;
    Vec3 width;
    Vec3 length;
};

PanelFrame frameOf(const RadiantHeater& heater)
{
    PanelFrame frame;
    frame.normal = heater.normal.normalized();
    frame.width = (heater.widthAxis - heater.widthAxis.dot(frame.normal) * frame.normal).normalized();
    frame.length = frame.normal.cross(frame.width);
    return frame;
}
} // namespace

void validate(const RadiantHeater& heater)
{
    if (!(heater.power >= 0) || !std::isfinite(heater.power))
    {
        throw InputError("power", "must be >= 0 W (got " + formatNumber(heater.power) + ")");
    }
    if (!(heater.width > 0) || !std::isfinite(heater.width))
    {
        throw InputError("width", "must be a positive number of m (got " + formatNumber(heater.width) + ")");
    }
    if (!(heater.length > 0) || !std::isfinite(heater.length))
    {
        throw InputError("length", "must be a positive number of m (got " + formatNumber(heater.length) + ")");
    }
    if (!heater.centre.allFinite())
    {
        throw InputError("centre", "must be finite");
    }
    if (!heater.normal.allFinite() || !(heater.normal.norm() > 0))
    {
        throw InputError("normal", "must be a non-zero direction");
    }
    const Vec3 n = heater.normal.normalized();
    if (!heater.widthAxis.allFinite() ||
        !((heater.widthAxis - heater.widthAxis.dot(n) * n).norm() > 1e-6 * heater.widthAxis.norm()))
    {
        throw InputError("widthAxis", "must be a direction not parallel to the normal");
    }
}

void validate(const HotAirZone& zone)
{
    if (!zone.minCorner.allFinite() || !zone.maxCorner.allFinite() ||
        !(zone.maxCorner.array() > zone.minCorner.array()).all())
    {
        throw InputError("maxCorner", "must exceed the min corner on every axis");
    }
    if (!(zone.temperature > 0) || !std::isfinite(zone.temperature))
    {
        throw InputError("temperature", "must be above absolute zero (got " + formatNumber(zone.temperature) + " K, " +
                                            formatNumber(zone.temperature - 273.15) + " C)");
    }
    if (!(zone.heatTransfer >= 0) || !std::isfinite(zone.heatTransfer))
    {
        throw InputError("heatTransfer", "must be >= 0 W/(m^2 K) (got " + formatNumber(zone.heatTransfer) + ")");
    }
}

std::array<Vec3, 4> heaterCorners(const RadiantHeater& heater)
{
    const PanelFrame f = frameOf(heater);
    const Vec3 w = Real(0.5) * heater.width * f.width;
    const Vec3 l = Real(0.5) * heater.length * f.length;
    // width x length = normal, so this order turns counter-clockwise about the normal.
    return {heater.centre - w - l, heater.centre + w - l, heater.centre + w + l, heater.centre - w + l};
}

Real viewFactorToHeater(const RadiantHeater& heater, const Vec3& x, const Vec3& n)
{
    const PanelFrame f = frameOf(heater);
    if (!((x - heater.centre).dot(f.normal) > 0))
    {
        return 0; // behind the panel, or in its plane
    }
    // Clip the panel to the patch's front half-space (Sutherland-Hodgman against one plane).
    const std::array<Vec3, 4> corners = heaterCorners(heater);
    const Real tolerance = Real(1e-12) * (heater.width + heater.length);
    // A quadrilateral clipped by one plane keeps at most five corners; on the stack, as this runs for every exposed
    // mass and heater at every step.
    std::array<Vec3, 8> polygon;
    std::size_t count = 0;
    for (std::size_t k = 0; k < corners.size(); ++k)
    {
        const Vec3& a = corners[k];
        const Vec3& b = corners[(k + 1) % corners.size()];
        const Real da = (a - x).dot(n) - tolerance;
        const Real db = (b - x).dot(n) - tolerance;
        if (da > 0)
        {
            polygon[count++] = a;
        }
        if ((da > 0) != (db > 0))
        {
            polygon[count++] = a + (da / (da - db)) * (b - a);
        }
    }
    if (count < 3)
    {
        return 0;
    }
    Real sum = 0;
    for (std::size_t k = 0; k < count; ++k)
    {
        const Vec3 r0 = polygon[k] - x;
        const Vec3 r1 = polygon[(k + 1) % count] - x;
        const Vec3 c = r0.cross(r1);
        const Real cn = c.norm();
        if (!(cn > 0))
        {
            continue;
        }
        sum += std::atan2(cn, r0.dot(r1)) * n.dot(c) / cn;
    }
    return std::abs(sum) / (Real(2) * std::numbers::pi_v<Real>);
}

Real heaterIrradiance(const RadiantHeater& heater, const Vec3& x, const Vec3& n)
{
    return heater.power / (heater.width * heater.length) * viewFactorToHeater(heater, x, n);
}
} // namespace masse
