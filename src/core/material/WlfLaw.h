#pragma once
/// The law every shipped material uses (`"law": "wlf"`, the default): a logistic step of the modulus and a WLF shift
/// of the viscosity, Arrhenius below the transition. Declared here for what builds materials in code (Material's
/// default, tests).
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
/// the material's upperTemperature (the model's range ends there; WLF is fitted for about Tt .. Tt + 50 K, physics.md
/// section 3).

#include "core/material/MaterialLaw.h"

namespace masse
{
/// Universal gas constant, J/(mol K).
inline constexpr Real gasConstant = 8.314462618;

/// Largest |log10 a_T| the shift reaches: a viscosity of 1e30 times eta(Tt) is solid for any simulated time.
inline constexpr Real maxLog10Shift = 30;

/// Defaults are high-impact polystyrene's (HIPS), as Material's are. Ranges are what validate() accepts.
class WlfLaw final : public MaterialLaw
{
public:
    Real glassyModulus = 2.0e9;          ///< Pa, E_g well below Tt; > rubberyModulus
    Real rubberyModulus = 1.0e6;         ///< Pa, E_r, the rubbery plateau well above Tt; > 0
    Real transitionWidth = 5;            ///< K, w of the modulus step; > 0
    Real wlfC1 = 17.44;                  ///< WLF C1 (physics.md: universal 17.44); > 0
    Real wlfC2 = 51.6;                   ///< K, WLF C2 (physics.md: universal 51.6 K); > 0
    Real viscosityAtTransition = 1.0e14; ///< Pa s, eta(Tt), the terminal (flow) shear viscosity; > 0
    /// J/mol, E_a of the Arrhenius shift below Tt; >= 0, where 0 (the default) matches the WLF slope at Tt.
    Real solidActivationEnergy = 0;

    Real modulusAt(const Material& material, Real temperature) const override;
    Real viscosityAt(const Material& material, Real temperature) const override;
    void validate(const Material& material) const override;

    /// log10 of the time-temperature shift a_T (0 at Tt, negative above, positive below).
    Real log10ShiftAt(const Material& material, Real temperature) const;
    /// The activation energy used below Tt (J/mol): solidActivationEnergy, or the WLF-slope match if that is 0.
    Real activationEnergyBelowTransition(const Material& material) const;
};
} // namespace masse
