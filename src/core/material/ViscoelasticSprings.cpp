#include "core/material/ViscoelasticSprings.h"

#include "core/Format.h"
#include "core/InputError.h"
#include "core/NamedEnum.h"
#include "core/NumericalError.h"
#include "core/Simulator.h"
#include "core/forces/Damping.h"
#include "core/parallel/TaskPool.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace masse
{
namespace
{
constexpr EnumName<SpringModel> springModelTable[] = {
    {SpringModel::Elastic, "elastic"},
    {SpringModel::Maxwell, "maxwell"},
    {SpringModel::Burgers, "burgers"},
};

/// Trouton's ratio: extensional over shear viscosity of an incompressible Newtonian liquid.
constexpr Real troutonRatio = 3;
/// Springs per chunk of the per-spring passes on the pool (each spring's parameters, step and state are its own).
constexpr std::size_t springChunkSize = 4096;
} // namespace

SpringModel parseSpringModel(std::string_view name)
{
    return parseEnum(springModelTable, name, "model", "spring model");
}

std::string_view springModelName(SpringModel model)
{
    return enumName(springModelTable, model);
}

std::vector<std::string> springModelNames()
{
    return namesOf(springModelTable);
}

void validate(const SpringModelSettings& settings)
{
    if (!(settings.dampingRatio >= 0 && settings.dampingRatio <= 1))
    {
        throw InputError("dampingRatio", "must be in [0, 1] (got " + formatNumber(settings.dampingRatio) + ")");
    }
    if (!(settings.strainHardening >= 0 && settings.strainHardening <= maxStrainHardening))
    {
        throw InputError("strainHardening", "must be in [0, " + formatNumber(maxStrainHardening) + "] (got " +
                                                formatNumber(settings.strainHardening) + ")");
    }
    if (!(settings.initialTemperature > 0) || !std::isfinite(settings.initialTemperature))
    {
        throw InputError("initialTemperature", "must be above absolute zero (got " +
                                                   formatNumber(settings.initialTemperature) + " K, " +
                                                   formatNumber(kelvinToCelsius(settings.initialTemperature)) + " C)");
    }
}

ViscoelasticSprings::ViscoelasticSprings(const MassSpringSystem& system, std::vector<Real> stiffnessPerModulus,
                                         const Material& material, const SpringModelSettings& settings)
    : m_material(material), m_settings(settings), m_perModulus(std::move(stiffnessPerModulus)),
      m_uniformTemperature(settings.initialTemperature)
{
    validate(m_material);
    validate(m_settings);
    const SpringSet& springs = system.springs;
    if (m_perModulus.size() != springs.size())
    {
        throw std::invalid_argument("ViscoelasticSprings: " + std::to_string(m_perModulus.size()) +
                                    " stiffness factors for " + std::to_string(springs.size()) + " springs");
    }
    for (std::size_t s = 0; s < m_perModulus.size(); ++s)
    {
        if (!(m_perModulus[s] > 0) || !std::isfinite(m_perModulus[s]))
        {
            throw InputError("stiffnessPerModulus[" + std::to_string(s) + "]",
                             "must be > 0 m (got " + formatNumber(m_perModulus[s]) + ")");
        }
    }
    m_originalLength = springs.restLength();
    m_reducedMass.resize(springs.size());
    const std::vector<Real>& mass = system.particles.mass;
    for (std::size_t s = 0; s < springs.size(); ++s)
    {
        const SpringEnds e = springs.ends()[s];
        m_reducedMass[s] = mass[e.a] * mass[e.b] / (mass[e.a] + mass[e.b]);
    }
    m_params.resize(springs.size());
    m_step.resize(springs.size());
    m_state.resize(springs.size());
    m_springTemperature.assign(springs.size(), std::numeric_limits<Real>::quiet_NaN());
    m_thicknessFactor.assign(springs.size(), Real(1));
}

void ViscoelasticSprings::setUniformTemperature(Real temperature)
{
    if (!(temperature > 0) || !std::isfinite(temperature))
    {
        throw InputError("temperature", "must be above absolute zero (got " + formatNumber(temperature) + " K)");
    }
    m_uniformTemperature = temperature;
}

bool ViscoelasticSprings::refreshParameters(const MassSpringSystem& system, std::span<const Real> temperature,
                                            SheetThickness* thickness)
{
    const SpringSet& springs = system.springs;
    if (!temperature.empty() && temperature.size() != system.massCount())
    {
        throw std::invalid_argument("ViscoelasticSprings: " + std::to_string(temperature.size()) +
                                    " temperatures for " + std::to_string(system.massCount()) + " masses");
    }
    const bool followThickness = m_settings.followThickness && thickness;
    const Real hardening = thickness ? m_settings.strainHardening : Real(0);
    const bool readsThickness = followThickness || hardening > 0;
    if (readsThickness)
    {
        thickness->update(system.particles.position);
    }
    constexpr Real infinity = std::numeric_limits<Real>::infinity();
    // Each spring on its own, over chunks on the pool; what a chunk found (a change, the first bad temperature) is
    // kept per chunk and read in chunk order, so the error named is the same at any thread count.
    const std::size_t chunks = chunkCount(springs.size(), springChunkSize);
    m_chunkChanged.assign(chunks, 0);
    m_chunkBadSpring.assign(chunks, springs.size());
    parallelFor(springs.size(), springChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    const std::size_t chunk = begin / springChunkSize;
                    for (std::size_t s = begin; s < end; ++s)
                    {
                        const SpringEnds e = springs.ends()[s];
                        const Real t = temperature.empty() ? m_uniformTemperature
                                                           : Real(0.5) * (temperature[e.a] + temperature[e.b]);
                        if (!(t > 0) || !std::isfinite(t))
                        {
                            m_chunkBadSpring[chunk] = std::min(m_chunkBadSpring[chunk], s);
                            continue;
                        }
                        // h/h0 at the spring: the mean of its ends'.
                        const Real thinning =
                            readsThickness ? Real(0.5) * (thickness->thickness()[e.a] + thickness->thickness()[e.b]) /
                                                 thickness->initialThickness()
                                           : Real(1);
                        Real factor = followThickness ? thinning : Real(1);
                        if (hardening > 0)
                        {
                            factor *= std::pow(thinning, -hardening);
                        }
                        if (t == m_springTemperature[s] && factor == m_thicknessFactor[s])
                        {
                            continue;
                        }
                        m_springTemperature[s] = t;
                        m_thicknessFactor[s] = factor;
                        m_chunkChanged[chunk] = 1;
                        const Real g = m_perModulus[s] * factor;
                        BurgersParams& p = m_params[s];
                        p.maxwellStiffness = g * modulusAt(m_material, t);
                        const Real dashpot = troutonRatio * g * viscosityAt(m_material, t);
                        switch (m_settings.model)
                        {
                        case SpringModel::Elastic:
                            p.maxwellDamping = infinity;
                            p.kelvinStiffness = infinity;
                            p.kelvinDamping = infinity;
                            break;
                        case SpringModel::Maxwell:
                            p.maxwellDamping = dashpot;
                            p.kelvinStiffness = infinity;
                            p.kelvinDamping = infinity;
                            break;
                        case SpringModel::Burgers:
                            p.maxwellDamping = dashpot;
                            p.kelvinStiffness = m_material.kelvinModulusRatio * p.maxwellStiffness;
                            p.kelvinDamping = m_material.kelvinViscosityRatio * dashpot;
                            break;
                        }
                    }
                });
    bool changed = false;
    for (std::size_t chunk = 0; chunk < chunks; ++chunk)
    {
        const std::size_t s = m_chunkBadSpring[chunk];
        if (s < springs.size())
        {
            const SpringEnds e = springs.ends()[s];
            const Real t =
                temperature.empty() ? m_uniformTemperature : Real(0.5) * (temperature[e.a] + temperature[e.b]);
            throw NumericalError("spring " + std::to_string(s) + " between masses " + std::to_string(e.a) + " and " +
                                 std::to_string(e.b) + " has temperature " + std::to_string(t) +
                                 " K: the temperatures are not finite and positive");
        }
        changed = changed || m_chunkChanged[chunk] != 0;
    }
    return changed;
}

void ViscoelasticSprings::start(const MassSpringSystem& system, const StepContext& context)
{
    refreshParameters(system, context.temperature, context.thickness);
    // The sheet starts as an elastic body at its construction temperature: any initial stretch is elastic strain.
    const SpringSet& springs = system.springs;
    const std::vector<Vec3>& x = system.particles.position;
    for (std::size_t s = 0; s < springs.size(); ++s)
    {
        const SpringEnds e = springs.ends()[s];
        BurgersState& state = m_state[s];
        state.extension = (x[e.a] - x[e.b]).norm() - m_originalLength[s];
        state.force = m_params[s].maxwellStiffness * state.extension;
        state.kelvinExtension = 0;
    }
    m_started = true;
}

void ViscoelasticSprings::rebuildSteps(MassSpringSystem& system, Real h, bool changedChunksOnly)
{
    std::vector<Real>& springStiffness = system.springs.mutableStiffness();
    std::vector<Real>& springDamping = system.springs.mutableDamping();
    const bool elastic = m_settings.model == SpringModel::Elastic;
    parallelFor(springStiffness.size(), springChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    if (changedChunksOnly && m_chunkChanged[begin / springChunkSize] == 0)
                    {
                        return; // its parameters and h are those its coefficients were built for
                    }
                    for (std::size_t s = begin; s < end; ++s)
                    {
                        m_step[s] = burgersStep(m_params[s], h);
                        const Real stiffness = elastic ? m_params[s].maxwellStiffness : Real(1) / m_step[s].compliance;
                        springStiffness[s] = stiffness;
                        springDamping[s] = Real(2) * m_settings.dampingRatio * std::sqrt(stiffness * m_reducedMass[s]);
                    }
                });
    m_stepLength = h;
}

void ViscoelasticSprings::writeRestLengths(MassSpringSystem& system)
{
    std::vector<Real>& restLength = system.springs.mutableRestLength();
    const bool elastic = m_settings.model == SpringModel::Elastic;
    parallelFor(restLength.size(), springChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    for (std::size_t s = begin; s < end; ++s)
                    {
                        restLength[s] = elastic ? m_originalLength[s]
                                                : m_originalLength[s] + burgersFreeExtension(m_step[s], m_state[s]);
                    }
                });
    // Rest lengths move every substep; the stability estimate and Verlet's cached force depend on them.
    system.markChanged();
}

void ViscoelasticSprings::beginFrame(MassSpringSystem& system, StepContext& context, Real /*time*/, Real dt)
{
    bool changed;
    if (!m_started)
    {
        start(system, context);
        changed = true;
    }
    else
    {
        changed = refreshParameters(system, context.temperature, context.thickness);
    }
    const Real h = m_stepLength > 0 ? m_stepLength : dt;
    if (changed || h != m_stepLength)
    {
        rebuildSteps(system, h, h == m_stepLength);
    }
    writeRestLengths(system);
}

void ViscoelasticSprings::afterSubstep(MassSpringSystem& system, StepContext& context, Real h, Real time)
{
    if (!m_started)
    {
        start(system, context); // stepped without beginFrame (an integrator driven by hand): start from here
    }
    const SpringSet& springs = system.springs;
    const std::vector<Vec3>& x = system.particles.position;
    if (h != m_stepLength)
    {
        rebuildSteps(system, h, false); // the state update below must use the step actually taken
    }
    const bool elastic = m_settings.model == SpringModel::Elastic;
    m_chunkFinite.assign(chunkCount(springs.size(), springChunkSize), 1);
    parallelFor(springs.size(), springChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    bool finite = true;
                    for (std::size_t s = begin; s < end; ++s)
                    {
                        const SpringEnds e = springs.ends()[s];
                        const Real extension = (x[e.a] - x[e.b]).norm() - m_originalLength[s];
                        BurgersState& state = m_state[s];
                        if (elastic)
                        {
                            state.force = m_params[s].maxwellStiffness * extension;
                            state.extension = extension;
                        }
                        else
                        {
                            const Real force = burgersForce(m_step[s], state, extension);
                            burgersAdvance(m_step[s], state, force, extension);
                        }
                        finite = finite && std::isfinite(state.force) && std::isfinite(state.kelvinExtension);
                    }
                    m_chunkFinite[begin / springChunkSize] = finite ? 1 : 0;
                });
    if (std::find(m_chunkFinite.begin(), m_chunkFinite.end(), std::uint8_t(0)) != m_chunkFinite.end())
    {
        for (std::size_t s = 0; s < springs.size(); ++s)
        {
            if (!std::isfinite(m_state[s].force) || !std::isfinite(m_state[s].kelvinExtension))
            {
                throw NumericalError("the spring model diverged at t = " + formatNumber(time) + " s: spring " +
                                     std::to_string(s) + " has a non-finite force or Kelvin extension");
            }
        }
    }
    writeRestLengths(system);
}
} // namespace masse
