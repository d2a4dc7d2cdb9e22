#include "Material.h"
#include "Format.h"

#include "InputError.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace masse
{
namespace
{
void requirePositive(Real value, const char* key, const char* unit)
{
    if (!(value > 0) || !std::isfinite(value))
    {
        throw InputError(std::string(key) + ": must be a positive number" + (*unit ? std::string(" of ") + unit : "") +
                         " (got " + formatNumber(value) + ")");
    }
}

/// Temperatures are named by their material-file keys, which are in celsius.
void requireTemperature(Real kelvin, const char* key)
{
    if (!(kelvin > 0) || !std::isfinite(kelvin))
    {
        throw InputError(std::string(key) + ": must be a finite temperature above absolute zero (got " +
                         formatNumber(kelvinToCelsius(kelvin)) + " C)");
    }
}

void requireBelow(Real lowKelvin, const char* lowKey, Real highKelvin, const char* highKey, const char* why)
{
    if (!(lowKelvin < highKelvin))
    {
        throw InputError(std::string(lowKey) + ": must be below " + highKey + " (" + why + "; got " +
                         formatNumber(kelvinToCelsius(lowKelvin)) + " C and " +
                         formatNumber(kelvinToCelsius(highKelvin)) + " C)");
    }
}
} // namespace

void validate(const Material& m)
{
    requirePositive(m.density, "density", "kg/m^3");
    requirePositive(m.specificHeat, "specific_heat", "J/(kg K)");
    requirePositive(m.conductivity, "conductivity", "W/(m K)");
    requireTemperature(m.glassTransition, "glass_transition_c");
    requireTemperature(m.transitionTemperature, "transition_c");
    requireTemperature(m.upperTemperature, "upper_c");
    requireBelow(m.glassTransition, "glass_transition_c", m.upperTemperature, "upper_c",
                 "the glass transition must lie inside the model's range");
    if (m.transitionTemperature < m.glassTransition)
    {
        throw InputError("transition_c: must be at or above glass_transition_c (got " +
                         formatNumber(kelvinToCelsius(m.transitionTemperature)) + " C and " +
                         formatNumber(kelvinToCelsius(m.glassTransition)) + " C)");
    }
    requireBelow(m.transitionTemperature, "transition_c", m.upperTemperature, "upper_c",
                 "flow must start inside the model's range");
    requirePositive(m.rubberyModulus, "rubbery_modulus", "Pa");
    requirePositive(m.glassyModulus, "glassy_modulus", "Pa");
    if (!(m.glassyModulus > m.rubberyModulus))
    {
        throw InputError("glassy_modulus: must exceed rubbery_modulus (got " + formatNumber(m.glassyModulus) +
                         " Pa and " + formatNumber(m.rubberyModulus) + " Pa)");
    }
    requirePositive(m.transitionWidth, "transition_width", "K");
    requirePositive(m.wlfC1, "wlf_c1", "");
    requirePositive(m.wlfC2, "wlf_c2", "K");
    requirePositive(m.viscosityAtTransition, "viscosity_at_transition", "Pa s");
    if (!(m.solidActivationEnergy >= 0) || !std::isfinite(m.solidActivationEnergy))
    {
        throw InputError("solid_activation_energy: must be >= 0 J/mol (got " + formatNumber(m.solidActivationEnergy) +
                         ")");
    }
    requirePositive(m.kelvinModulusRatio, "kelvin_modulus_ratio", "");
    requirePositive(m.kelvinViscosityRatio, "kelvin_viscosity_ratio", "");

    const FormingWindow& f = m.forming;
    requireTemperature(f.set, "forming_window.set_c");
    requireTemperature(f.lower, "forming_window.lower_c");
    requireTemperature(f.normal, "forming_window.normal_c");
    requireTemperature(f.upper, "forming_window.upper_c");
    requireBelow(f.set, "forming_window.set_c", f.lower, "forming_window.lower_c",
                 "a part must set below the forming temperatures");
    if (!(f.lower <= f.normal && f.normal <= f.upper))
    {
        throw InputError("forming_window.normal_c: must lie between lower_c and upper_c (got " +
                         formatNumber(kelvinToCelsius(f.lower)) + ", " + formatNumber(kelvinToCelsius(f.normal)) +
                         ", " + formatNumber(kelvinToCelsius(f.upper)) + " C)");
    }
}

Real modulusAt(const Material& m, Real temperature)
{
    // exp overflows to infinity far above Tt, which makes the glassy share exactly 0: no NaN.
    const Real glassyShare =
        Real(1) / (Real(1) + std::exp((temperature - m.transitionTemperature) / m.transitionWidth));
    const Real logRubbery = std::log(m.rubberyModulus);
    const Real logGlassy = std::log(m.glassyModulus);
    return std::exp(logRubbery + (logGlassy - logRubbery) * glassyShare);
}

Real activationEnergyBelowTransition(const Material& m)
{
    if (m.solidActivationEnergy > 0)
    {
        return m.solidActivationEnergy;
    }
    const Real tt = m.transitionTemperature;
    return std::log(Real(10)) * m.wlfC1 * gasConstant * tt * tt / m.wlfC2;
}

Real log10ShiftAt(const Material& m, Real temperature)
{
    const Real tt = m.transitionTemperature;
    if (!(temperature > 0))
    {
        return maxLog10Shift;
    }
    Real shift;
    if (temperature >= tt)
    {
        const Real above = std::min(temperature, m.upperTemperature) - tt;
        shift = -m.wlfC1 * above / (m.wlfC2 + above);
    }
    else
    {
        const Real lnShift = activationEnergyBelowTransition(m) / gasConstant * (Real(1) / temperature - Real(1) / tt);
        shift = lnShift / std::log(Real(10));
    }
    return std::clamp(shift, -maxLog10Shift, maxLog10Shift);
}

Real viscosityAt(const Material& m, Real temperature)
{
    return m.viscosityAtTransition * std::pow(Real(10), log10ShiftAt(m, temperature));
}
} // namespace masse
