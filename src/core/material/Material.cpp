#include "core/material/Material.h"
#include "core/Format.h"

#include "core/InputError.h"

#include <cmath>

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
    if (!m.law)
    {
        throw InputError("law", "is missing");
    }
    m.law->validate(m);
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
} // namespace masse
