// "law": "wlf", the logistic modulus step and the WLF/Arrhenius viscosity shift of WlfLaw.h.

#include "core/material/WlfLaw.h"

#include "core/Format.h"
#include "core/InputError.h"
#include "core/material/Material.h"

#include <algorithm>
#include <cmath>

namespace masse
{
namespace
{
void requirePositiveParameter(Real value, const char* field, const char* unit)
{
    if (!(value > 0) || !std::isfinite(value))
    {
        throw InputError(field, std::string("must be a positive number") + (*unit ? std::string(" of ") + unit : "") +
                                    " (got " + formatNumber(value) + ")");
    }
}

std::shared_ptr<const MaterialLaw> readWlfLaw(const LawKeys& keys)
{
    auto law = std::make_shared<WlfLaw>();
    law->glassyModulus = keys.number("glassy_modulus");
    law->rubberyModulus = keys.number("rubbery_modulus");
    law->transitionWidth = keys.number("transition_width", law->transitionWidth);
    law->wlfC1 = keys.number("wlf_c1", law->wlfC1);
    law->wlfC2 = keys.number("wlf_c2", law->wlfC2);
    law->viscosityAtTransition = keys.number("viscosity_at_transition");
    law->solidActivationEnergy = keys.number("solid_activation_energy", law->solidActivationEnergy);
    return law;
}

constexpr LawParameterKey wlfLawKeys[] = {{"glassyModulus", "glassy_modulus"},
                                          {"rubberyModulus", "rubbery_modulus"},
                                          {"transitionWidth", "transition_width"},
                                          {"wlfC1", "wlf_c1"},
                                          {"wlfC2", "wlf_c2"},
                                          {"viscosityAtTransition", "viscosity_at_transition"},
                                          {"solidActivationEnergy", "solid_activation_energy"}};
} // namespace

void WlfLaw::validate(const Material&) const
{
    requirePositiveParameter(rubberyModulus, "rubberyModulus", "Pa");
    requirePositiveParameter(glassyModulus, "glassyModulus", "Pa");
    if (!(glassyModulus > rubberyModulus))
    {
        throw InputError("glassyModulus", "must exceed the rubbery modulus (got " + formatNumber(glassyModulus) +
                                              " Pa and " + formatNumber(rubberyModulus) + " Pa)");
    }
    requirePositiveParameter(transitionWidth, "transitionWidth", "K");
    requirePositiveParameter(wlfC1, "wlfC1", "");
    requirePositiveParameter(wlfC2, "wlfC2", "K");
    requirePositiveParameter(viscosityAtTransition, "viscosityAtTransition", "Pa s");
    if (!(solidActivationEnergy >= 0) || !std::isfinite(solidActivationEnergy))
    {
        throw InputError("solidActivationEnergy",
                         "must be >= 0 J/mol (got " + formatNumber(solidActivationEnergy) + ")");
    }
}

Real WlfLaw::modulusAt(const Material& m, Real temperature) const
{
    // exp overflows to infinity far above Tt, which makes the glassy share exactly 0: no NaN.
    const Real glassyShare = Real(1) / (Real(1) + std::exp((temperature - m.transitionTemperature) / transitionWidth));
    const Real logRubbery = std::log(rubberyModulus);
    const Real logGlassy = std::log(glassyModulus);
    return std::exp(logRubbery + (logGlassy - logRubbery) * glassyShare);
}

Real WlfLaw::activationEnergyBelowTransition(const Material& m) const
{
    if (solidActivationEnergy > 0)
    {
        return solidActivationEnergy;
    }
    const Real tt = m.transitionTemperature;
    return std::log(Real(10)) * wlfC1 * gasConstant * tt * tt / wlfC2;
}

Real WlfLaw::log10ShiftAt(const Material& m, Real temperature) const
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
        shift = -wlfC1 * above / (wlfC2 + above);
    }
    else
    {
        const Real lnShift = activationEnergyBelowTransition(m) / gasConstant * (Real(1) / temperature - Real(1) / tt);
        shift = lnShift / std::log(Real(10));
    }
    return std::clamp(shift, -maxLog10Shift, maxLog10Shift);
}

Real WlfLaw::viscosityAt(const Material& m, Real temperature) const
{
    return viscosityAtTransition * std::pow(Real(10), log10ShiftAt(m, temperature));
}

extern const MaterialLawEntry wlfLawEntry = {
    .name = "wlf",
    .read = readWlfLaw,
    .keys = wlfLawKeys,
};
} // namespace masse
