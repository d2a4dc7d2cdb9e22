#include "core/material/Material.h"
#include "core/Format.h"

#include "core/InputError.h"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace masse
{
namespace
{
void requirePositive(Real value, const char* field, const char* unit)
{
    if (!(value > 0) || !std::isfinite(value))
    {
        throw InputError(field, std::string("must be a positive number") + (*unit ? std::string(" of ") + unit : "") +
                                    " (got " + formatNumber(value) + ")");
    }
}

/// Temperatures are shown in celsius as well as kelvin: materials are described in celsius.
std::string temperatureText(Real kelvin)
{
    return formatNumber(kelvinToCelsius(kelvin)) + " C";
}

void requireTemperature(Real kelvin, const char* field)
{
    if (!(kelvin > 0) || !std::isfinite(kelvin))
    {
        throw InputError(field,
                         "must be a finite temperature above absolute zero (got " + temperatureText(kelvin) + ")");
    }
}

/// `high` names the other temperature in words, for a reader who knows the material but not this struct.
void requireBelow(Real lowKelvin, const char* lowField, Real highKelvin, const char* high, const char* why)
{
    if (!(lowKelvin < highKelvin))
    {
        throw InputError(lowField, std::string("must be below the ") + high + " (" + why + "; got " +
                                       temperatureText(lowKelvin) + " and " + temperatureText(highKelvin) + ")");
    }
}
} // namespace

void validate(const Material& m)
{
    requirePositive(m.density, "density", "kg/m^3");
    requirePositive(m.specificHeat, "specificHeat", "J/(kg K)");
    requirePositive(m.conductivity, "conductivity", "W/(m K)");
    requireTemperature(m.glassTransition, "glassTransition");
    requireTemperature(m.transitionTemperature, "transitionTemperature");
    requireTemperature(m.upperTemperature, "upperTemperature");
    requireBelow(m.glassTransition, "glassTransition", m.upperTemperature, "upper temperature",
                 "the glass transition must lie inside the model's range");
    if (m.transitionTemperature < m.glassTransition)
    {
        throw InputError("transitionTemperature", "must be at or above the glass transition (got " +
                                                      temperatureText(m.transitionTemperature) + " and " +
                                                      temperatureText(m.glassTransition) + ")");
    }
    requireBelow(m.transitionTemperature, "transitionTemperature", m.upperTemperature, "upper temperature",
                 "flow must start inside the model's range");
    requirePositive(m.rubberyModulus, "rubberyModulus", "Pa");
    requirePositive(m.glassyModulus, "glassyModulus", "Pa");
    if (!(m.glassyModulus > m.rubberyModulus))
    {
        throw InputError("glassyModulus", "must exceed the rubbery modulus (got " + formatNumber(m.glassyModulus) +
                                              " Pa and " + formatNumber(m.rubberyModulus) + " Pa)");
    }
    requirePositive(m.transitionWidth, "transitionWidth", "K");
    requirePositive(m.wlfC1, "wlfC1", "");
    requirePositive(m.wlfC2, "wlfC2", "K");
    requirePositive(m.viscosityAtTransition, "viscosityAtTransition", "Pa s");
    if (!(m.solidActivationEnergy >= 0) || !std::isfinite(m.solidActivationEnergy))
    {
        throw InputError("solidActivationEnergy",
                         "must be >= 0 J/mol (got " + formatNumber(m.solidActivationEnergy) + ")");
    }
    requirePositive(m.kelvinModulusRatio, "kelvinModulusRatio", "");
    requirePositive(m.kelvinViscosityRatio, "kelvinViscosityRatio", "");

    const FormingWindow& f = m.forming;
    requireTemperature(f.set, "forming.set");
    requireTemperature(f.lower, "forming.lower");
    requireTemperature(f.normal, "forming.normal");
    requireTemperature(f.upper, "forming.upper");
    requireBelow(f.set, "forming.set", f.lower, "lower forming temperature",
                 "a part must set below the forming temperatures");
    if (!(f.lower <= f.normal && f.normal <= f.upper))
    {
        throw InputError("forming.normal", "must lie between the lower and the upper forming temperature (got " +
                                               temperatureText(f.lower) + ", " + temperatureText(f.normal) + ", " +
                                               temperatureText(f.upper) + ")");
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
