#pragma once
/// A thermoplastic sheet material and how its stiffness and viscosity follow temperature.
///
/// Temperatures are in kelvin inside the engine (material files give them in celsius, in keys ending in "_c").
///
/// Modulus: a smooth step in log E from the glassy value to the rubbery plateau, centred on the transition
/// temperature Tt (the glass transition for amorphous polymers):
///     log E(T) = log E_r + (log E_g - log E_r) s(T),   s(T) = 1 / (1 + exp((T - Tt) / w))
/// so E falls about three decades within a few widths w of Tt (physics.md section 3: 2-3 GPa to 0.5-3 MPa). A
/// logistic in log E has no kinks: stiffness changes smoothly as a sheet heats and cools through Tt.
///
/// Viscosity: eta(T) = eta(Tt) a_T with the time-temperature shift a_T
///     above Tt, WLF:        log10 a_T = -C1 (T - Tt) / (C2 + T - Tt)
///     below Tt, Arrhenius:  ln a_T = (E_a / R) (1/T - 1/Tt)
/// For amorphous polymers E_a is left at 0, which means the activation energy whose slope d ln a_T / dT matches the
/// WLF slope at Tt, E_a = ln(10) C1 R Tt^2 / C2 (about 900 kJ/mol for Tg = 100 C): the curve is smooth at Tt and
/// needs no extra parameter, and the viscosity climbs past 1e20 Pa s within some 20 K below Tt: flow stops, which is
/// what freezes a cooled sheet's shape. A semicrystalline polymer sets E_a itself, large, to stand for its crystals
/// melting. log10 a_T is capped at +/-maxLog10Shift so that nothing overflows, and WLF is evaluated at no more than
/// upperTemperature (the model's range ends there; WLF is fitted for about Tt .. Tt + 50 K, physics.md section 3).
///
/// Delayed elasticity (the Kelvin-Voigt element of a Burgers spring) has no data in physics.md; it is set by two
/// ratios to the Maxwell values, E_K = kelvinModulusRatio E(T) and eta_K = kelvinViscosityRatio eta(T), so it shifts
/// with temperature like the rest of the material.

#include "core/Types.h"

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
/// data/materials/hips.json (a test checks they agree). Ranges are what validate() accepts.
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
    Real glassyModulus = 2.0e9;                   ///< Pa, E_g well below Tt; > rubberyModulus
    Real rubberyModulus = 1.0e6;                  ///< Pa, E_r, the rubbery plateau well above Tt; > 0
    Real transitionWidth = 5;                     ///< K, w of the modulus step; > 0
    Real wlfC1 = 17.44;                           ///< WLF C1 (physics.md: universal 17.44); > 0
    Real wlfC2 = 51.6;                            ///< K, WLF C2 (physics.md: universal 51.6 K); > 0
    Real viscosityAtTransition = 1.0e14;          ///< Pa s, eta(Tt), the terminal (flow) shear viscosity; > 0
    /// J/mol, E_a of the Arrhenius shift below Tt; >= 0, where 0 (the default) matches the WLF slope at Tt.
    Real solidActivationEnergy = 0;
    Real kelvinModulusRatio = 1.0;    ///< E_K / E of the Burgers spring's Kelvin element; > 0
    Real kelvinViscosityRatio = 0.05; ///< eta_K / eta of the Kelvin element; > 0
    FormingWindow forming;
};

/// Universal gas constant, J/(mol K).
inline constexpr Real gasConstant = 8.314462618;

/// The activation energy used below Tt (J/mol): solidActivationEnergy, or the WLF-slope match if that is 0.
Real activationEnergyBelowTransition(const Material& material);

/// Largest |log10 a_T| the shift reaches: a viscosity of 1e30 times eta(Tt) is solid for any simulated time.
inline constexpr Real maxLog10Shift = 30;

/// Throws InputError naming the first bad field as this struct names it (e.g. "conductivity: must be a positive
/// number of W/(m K) (got -0.1)", "glassTransition: must be below the upper temperature ...", "forming.lower: ...").
void validate(const Material& material);

/// Young's modulus E(T) in Pa.
Real modulusAt(const Material& material, Real temperature);
/// log10 of the time-temperature shift a_T (0 at Tt, negative above, positive below).
Real log10ShiftAt(const Material& material, Real temperature);
/// Shear viscosity eta(T) = eta(Tt) a_T in Pa s.
Real viscosityAt(const Material& material, Real temperature);
} // namespace masse
