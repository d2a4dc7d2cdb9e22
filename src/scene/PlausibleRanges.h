#pragma once
/// Plausible ranges of the scene keys with a unit: far wider than any forming scene needs, so that a unit mistake (a
/// thickness in millimetres, a temperature in kelvin, a density in g/cm^3) or a number no machine has (a sheet corner
/// at -1e308 m, a gravity of 1e100 m/s^2) is refused when the file is read, naming the key and the likely mistake,
/// instead of running to a wrong end. data/scenes/README.md ("Plausible ranges") lists them.

#include "scene/json/JsonObject.h"

#include "core/Types.h"
#include "core/material/Material.h"

#include <string>

namespace masse::scene::plausible
{
constexpr Real maxCoordinate = 1e3; ///< m, |x|, |y| and |z| of any point a scene places (machines are metres across)
constexpr Real maxLength = 1e3;     ///< m, any size: half extents, prism sides, heater sides, wall thickness
constexpr Real maxMeshScale = 1e3;  ///< a mesh file's scale factor
constexpr Real maxGravity = 1e3;    ///< m/s^2, about 100 g (Earth's is 9.81)
constexpr Real minThickness = 1e-5; ///< m, 0.01 mm: a thin film
constexpr Real maxThickness = 0.05; ///< m, 50 mm: thicker than any sheet a forming machine heats
constexpr Real minDensity = 10;     ///< kg/m^3, a light foam
constexpr Real maxDensity = 25000;  ///< kg/m^3, beyond the densest metals
constexpr Real maxGrabForce = 1e6;  ///< N, a grab's cap
constexpr Real maxSteerSpeed =
    100; ///< m/s, a steered obstacle's: a forming machine's plug moves at most metres a second
constexpr Real maxSheetHeight = 0.5; ///< m, the sheet box's height (its layers' span): half a metre is a block
constexpr Real minHeaterSide = 0.01; ///< m, a heater panel's width or length
constexpr Real maxHeaterSide = 10;   ///< m, wider than any forming machine's heater bank
constexpr Real minHeaterFlux = 100;  ///< W/m^2 of a heater's face when it has power: a tenth of sunlight
constexpr Real maxHeaterFlux = 1e6;  ///< W/m^2, beyond quartz lamps (some 100 to 200 kW/m^2)

/// A point (m) at `key`: finite, each coordinate within +-maxCoordinate.
Vec3 point(const JsonObject& o, const std::string& key);
Vec3 point(const JsonObject& o, const std::string& key, const Vec3& fallback);
/// Throws naming `key` when `p` is not a plausible point.
void checkPoint(const JsonObject& o, const std::string& key, const Vec3& p);
/// A size (m) in (0, maxLength]; `value` as read.
void checkLength(const JsonObject& o, const std::string& key, Real value);
/// A gravity vector (m/s^2) at `key`, its length at most maxGravity.
Vec3 gravity(const JsonObject& o, const std::string& key);
Vec3 gravity(const JsonObject& o, const std::string& key, const Vec3& fallback);
/// A sheet thickness (m) in [minThickness, maxThickness]; a value in millimetres is named so.
Real thickness(const JsonObject& o, const std::string& key, Real fallback);
/// A density (kg/m^3) in [minDensity, maxDensity]; a value in g/cm^3 is named so.
Real density(const JsonObject& o, const std::string& key);
/// Throws naming `key` (the sheet's max) when the sheet box from `minCorner` to `maxCorner` is taller than
/// maxSheetHeight; a height in millimetres is named so.
void checkSheetHeight(const JsonObject& o, const std::string& key, const Vec3& minCorner, const Vec3& maxCorner);
/// A heater's side (m) in [minHeaterSide, maxHeaterSide]; a side in millimetres is named so.
void checkHeaterSide(const JsonObject& o, const std::string& key, Real value);
/// A heater's power (W): 0 (no power), or its flux over the face of `width` x `length` m in [minHeaterFlux,
/// maxHeaterFlux]; a power in kilowatts is named so.
void checkHeaterPower(const JsonObject& o, const std::string& key, Real power, Real width, Real length);
/// Throws "<key>: 293 C is above the material's 205 C upper limit (...); kelvin? ..." for a temperature (K) above
/// the material's upperTemperature: the sheet would start, or be driven, past the end of the material's model. The
/// kelvin question is asked when the number read as kelvin is a temperature the material's model holds.
void checkTemperature(const JsonObject& o, const std::string& key, Real kelvin, const Material& material);
} // namespace masse::scene::plausible
