#include "scene/PlausibleRanges.h"

#include "core/Format.h"

#include <cmath>

namespace masse::scene::plausible
{
namespace
{
std::string listed(const Vec3& v)
{
    return formatNumber(v.x()) + ", " + formatNumber(v.y()) + ", " + formatNumber(v.z());
}
} // namespace

void checkPoint(const JsonObject& o, const std::string& key, const Vec3& p)
{
    if (!p.allFinite() || p.cwiseAbs().maxCoeff() > maxCoordinate)
    {
        o.fail(key, "(" + listed(p) + ") m is farther than " + formatNumber(maxCoordinate) +
                        " m from the origin along an axis: no forming machine is that large (lengths are in metres)");
    }
}

Vec3 point(const JsonObject& o, const std::string& key)
{
    const Vec3 p = o.vec3(key);
    checkPoint(o, key, p);
    return p;
}

Vec3 point(const JsonObject& o, const std::string& key, const Vec3& fallback)
{
    return o.has(key) ? point(o, key) : fallback;
}

void checkLength(const JsonObject& o, const std::string& key, Real value)
{
    if (value > maxLength)
    {
        o.fail(key, formatNumber(value) + " m is longer than " + formatNumber(maxLength) +
                        " m: no forming machine is that large (lengths are in metres)");
    }
}

Vec3 gravity(const JsonObject& o, const std::string& key)
{
    const Vec3 g = o.vec3(key);
    if (g.stableNorm() > maxGravity) // stableNorm: the squares of 1e200 overflow
    {
        o.fail(key, formatNumber(g.stableNorm()) + " m/s^2 is beyond the plausible " + formatNumber(maxGravity) +
                        " m/s^2 (about 100 g; Earth's is 9.81 m/s^2)");
    }
    return g;
}

Vec3 gravity(const JsonObject& o, const std::string& key, const Vec3& fallback)
{
    return o.has(key) ? gravity(o, key) : fallback;
}

Real thickness(const JsonObject& o, const std::string& key, Real fallback)
{
    const Real value = o.positive(key, fallback);
    if (value >= minThickness && value <= maxThickness)
    {
        return value;
    }
    std::string message = formatNumber(value) + " m is outside a sheet's plausible " +
                          formatNumber(minThickness * 1e3) + " mm to " + formatNumber(maxThickness * 1e3) + " mm";
    const Real metres = value / 1e3;
    if (metres >= minThickness && metres <= maxThickness)
    {
        message += ": did you mean " + formatNumber(metres) + " (" + formatNumber(value) + " mm)?";
    }
    o.fail(key, message);
}

Real density(const JsonObject& o, const std::string& key)
{
    const Real value = o.number(key);
    if (value >= minDensity && value <= maxDensity)
    {
        return value;
    }
    std::string message = formatNumber(value) + " kg/m^3 is outside the plausible " + formatNumber(minDensity) +
                          " to " + formatNumber(maxDensity) + " kg/m^3";
    const Real perCubicMetre = value * 1e3;
    if (perCubicMetre >= minDensity && perCubicMetre <= maxDensity)
    {
        message += ": did you mean " + formatNumber(perCubicMetre) + " (" + formatNumber(value) + " g/cm^3)?";
    }
    o.fail(key, message);
}

void checkSheetHeight(const JsonObject& o, const std::string& key, const Vec3& minCorner, const Vec3& maxCorner)
{
    const Real height = maxCorner.y() - minCorner.y();
    if (!(height > maxSheetHeight))
    {
        return;
    }
    std::string message = "the sheet's box is " + formatNumber(height) + " m tall (min y " +
                          formatNumber(minCorner.y()) + " to max y " + formatNumber(maxCorner.y()) +
                          "), beyond a sheet's plausible " + formatNumber(maxSheetHeight) + " m";
    const Real metres = height / 1e3;
    if (metres <= maxSheetHeight)
    {
        message += ": did you mean a max y of " + formatNumber(minCorner.y() + metres) + " (" + formatNumber(height) +
                   " mm above min y)?";
    }
    o.fail(key, message);
}

void checkHeaterSide(const JsonObject& o, const std::string& key, Real value)
{
    if (value >= minHeaterSide && value <= maxHeaterSide)
    {
        return;
    }
    std::string message = formatNumber(value) + " m is outside a heater panel's plausible " +
                          formatNumber(minHeaterSide) + " to " + formatNumber(maxHeaterSide) + " m";
    const Real metres = value / 1e3;
    if (metres >= minHeaterSide && metres <= maxHeaterSide)
    {
        message += ": did you mean " + formatNumber(metres) + " (" + formatNumber(value) + " mm)?";
    }
    o.fail(key, message);
}

void checkHeaterPower(const JsonObject& o, const std::string& key, Real power, Real width, Real length)
{
    const Real area = width * length;
    const Real flux = power / area;
    if (!(power > 0) || (flux >= minHeaterFlux && flux <= maxHeaterFlux))
    {
        return; // (a negative power is the heat model's to refuse)
    }
    std::string message = formatNumber(power) + " W from a " + formatNumber(width) + " m x " + formatNumber(length) +
                          " m panel is " + formatNumber(flux) + " W/m^2, outside a radiant heater's plausible " +
                          formatNumber(minHeaterFlux) + " to " + formatNumber(maxHeaterFlux) + " W/m^2";
    const Real watts = power * 1e3;
    if (watts / area >= minHeaterFlux && watts / area <= maxHeaterFlux)
    {
        message += ": did you mean " + formatNumber(watts) + " (" + formatNumber(power) + " kW)?";
    }
    o.fail(key, message);
}

void checkTemperature(const JsonObject& o, const std::string& key, Real kelvin, const Material& material)
{
    if (!(kelvin > material.upperTemperature))
    {
        return;
    }
    const Real given = kelvinToCelsius(kelvin);
    std::string message = formatNumber(given) + " C is above the material's " +
                          formatNumber(kelvinToCelsius(material.upperTemperature)) + " C upper limit (" +
                          material.name + "'s upper_c, where its model ends)";
    const Real asKelvin = kelvinToCelsius(given);
    if (given > 0 && asKelvin <= kelvinToCelsius(material.upperTemperature))
    {
        message += "; kelvin? " + formatNumber(given) + " K is " + formatNumber(asKelvin) + " C";
    }
    o.fail(key, message);
}
} // namespace masse::scene::plausible
