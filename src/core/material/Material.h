#pragma once
/// A thermoplastic sheet material: its mass, heat and forming temperatures, and the law (MaterialLaw.h) by which its
/// stiffness and viscosity follow temperature.
///
/// Temperatures are in kelvin inside the engine (material files give them in celsius, in keys ending in "_c").
///
/// Delayed elasticity (the Kelvin-Voigt element of a Burgers spring) has no data in physics.md; it is set by two
/// ratios to the Maxwell values, E_K = kelvinModulusRatio E(T) and eta_K = kelvinViscosityRatio eta(T), so it shifts
/// with temperature like the rest of the material.

#include "core/Types.h"
#include "core/material/WlfLaw.h"

#include <memory>
#include <string>

namespace masse
{
/// Converts degrees celsius to kelvin.
inline constexpr Real celsiusToKelvin(Real celsius)
{
    return celsius + Real(273.15);
}
inline constexpr Real kelvinToCelsius(Real kelvin)
{
    return kelvin - Real(273.15);
}

/// Temperatures at which a sheet is formed (physics.md section 3 gives ABS's: lower 127 C, normal 149-154 C,
/// upper 182 C, set 85 C). Informative for scenes and reports; the mechanics follow the modulus and viscosity curves.
struct FormingWindow
{
    Real lower = celsiusToKelvin(120);  ///< K, coolest sheet temperature that still forms
    Real normal = celsiusToKelvin(135); ///< K, usual forming temperature
    Real upper = celsiusToKelvin(160);  ///< K, hottest before the sheet sags or degrades too much
    Real set = celsiusToKelvin(80);     ///< K, below this a formed part keeps its shape and can leave the mould
};

/// Defaults are high-impact polystyrene (HIPS): the figures of physics.md section 3 for PS, and the same as
/// data/materials/hips.json (a test checks they agree), with WlfLaw's defaults. Ranges are what validate() accepts.
struct Material
{
    std::string name = "HIPS";
    Real density = 1050;                         ///< kg/m^3, > 0
    Real specificHeat = 1300;                    ///< J/(kg K), > 0
    Real conductivity = 0.15;                    ///< W/(m K), > 0
    Real glassTransition = celsiusToKelvin(100); ///< K, Tg, > 0
    /// K, Tt: where the modulus falls and viscous flow starts; the glass transition for amorphous polymers (PS, ABS,
    /// PMMA, PET), the crystalline melt for semicrystalline ones (PP, whose Tg is below room temperature).
    /// Range [glassTransition, upperTemperature).
    Real transitionTemperature = celsiusToKelvin(100);
    Real upperTemperature = celsiusToKelvin(200); ///< K, top of the model's range (viscosity stops falling); > Tt
    Real kelvinModulusRatio = 1.0;                ///< E_K / E of the Burgers spring's Kelvin element; > 0
    Real kelvinViscosityRatio = 0.05;             ///< eta_K / eta of the Kelvin element; > 0
    FormingWindow forming;
    /// How the modulus and viscosity follow temperature, with the law's own parameters; never null.
    std::shared_ptr<const MaterialLaw> law = std::make_shared<const WlfLaw>();
};

/// Throws InputError naming the first bad field as this struct or its law names it (e.g. "conductivity: must be a
/// positive number of W/(m K) (got -0.1)", "glassTransition: must be below the upper temperature ...",
/// "glassyModulus: ...", "forming.lower: ...").
void validate(const Material& material);

/// Young's modulus E(T) in Pa, by the material's law.
inline Real modulusAt(const Material& material, Real temperature)
{
    return material.law->modulusAt(material, temperature);
}
/// Shear viscosity eta(T) in Pa s, by the material's law.
inline Real viscosityAt(const Material& material, Real temperature)
{
    return material.law->viscosityAt(material, temperature);
}
} // namespace masse
