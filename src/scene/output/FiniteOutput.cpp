#include "scene/output/FiniteOutput.h"

#include "core/Format.h"
#include "core/NumericalError.h"

#include <cmath>
#include <string>

namespace masse::scene
{
namespace
{
void walk(const nlohmann::json& value, const std::string& path, const std::string& what)
{
    if (value.is_number_float() && !std::isfinite(value.get<double>()))
    {
        throw NumericalError("the run went beyond the range of double precision: " + what + " " + path +
                             " is not a finite number (nothing of this run is written)");
    }
    if (value.is_object())
    {
        for (auto it = value.begin(); it != value.end(); ++it)
        {
            walk(it.value(), path.empty() ? it.key() : path + "." + it.key(), what);
        }
    }
    else if (value.is_array())
    {
        for (std::size_t i = 0; i < value.size(); ++i)
        {
            walk(value[i], path + "[" + std::to_string(i) + "]", what);
        }
    }
}
} // namespace

void requireFiniteState(const Scene& scene)
{
    const Particles& p = scene.system().particles;
    Real total = 0;
    for (std::size_t i = 0; i < p.size(); ++i)
    {
        const Real energy = Real(0.5) * p.mass[i] * p.velocity[i].squaredNorm();
        if (!std::isfinite(p.position[i].norm()) || !std::isfinite(energy))
        {
            throw NumericalError(
                "the run went beyond the range of double precision at t = " + formatNumber(scene.time()) + " s: mass " +
                std::to_string(i) +
                (std::isfinite(p.position[i].norm()) ? "'s speed or kinetic energy" : "'s distance from the origin") +
                " is not a finite number (nothing of this run is written)");
        }
        total += energy;
    }
    if (!std::isfinite(total))
    {
        throw NumericalError("the run went beyond the range of double precision at t = " + formatNumber(scene.time()) +
                             " s: the sheet's kinetic energy is not a finite number (nothing of this run is written)");
    }
}

void requireFiniteJson(const nlohmann::json& document, const std::string& what)
{
    walk(document, "", what);
}
} // namespace masse::scene
