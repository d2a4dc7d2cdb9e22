#include "core/material/ThermalModel.h"
#include "core/Format.h"

#include "core/InputError.h"
#include "core/NumericalError.h"
#include "core/Simulator.h"
#include "core/parallel/TaskPool.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <tuple>

namespace masse
{
namespace
{
/// Springs per chunk of the conductances' pass on the pool.
constexpr std::size_t conductanceChunkSize = 8192;
constexpr std::uint8_t bottomFace = 1;
constexpr std::uint8_t topFace = 2;

/// cot of the angle at vertex o between the edges to a and b.
Real cotangent(const Vec3& o, const Vec3& a, const Vec3& b)
{
    const Vec3 e1 = a - o;
    const Vec3 e2 = b - o;
    const Real sine = e1.cross(e2).norm();
    return sine > 0 ? e1.dot(e2) / sine : Real(0);
}
} // namespace

void validate(const ThermalSettings& s)
{
    auto temperature = [](Real kelvin, const char* field)
    {
        if (!(kelvin > 0) || !std::isfinite(kelvin))
        {
            throw InputError(field, "must be above absolute zero (got " + formatNumber(kelvin) + " K, " +
                                        formatNumber(kelvin - 273.15) + " C)");
        }
    };
    temperature(s.initialTemperature, "initialTemperature");
    temperature(s.airTemperature, "airTemperature");
    if (!(s.airHeatTransfer >= 0) || !std::isfinite(s.airHeatTransfer))
    {
        throw InputError("airHeatTransfer", "must be >= 0 W/(m^2 K) (got " + formatNumber(s.airHeatTransfer) + ")");
    }
    if (!(s.absorptivity >= 0 && s.absorptivity <= 1))
    {
        throw InputError("absorptivity", "must be in [0, 1] (got " + formatNumber(s.absorptivity) + ")");
    }
    if (!(s.contactHeatTransfer >= 0) || !std::isfinite(s.contactHeatTransfer))
    {
        throw InputError("contactHeatTransfer",
                         "must be >= 0 W/(m^2 K) (got " + formatNumber(s.contactHeatTransfer) + ")");
    }
    if (!(s.solverTolerance > 0 && s.solverTolerance <= 1e-3))
    {
        throw InputError("solverTolerance", "must be in (0, 1e-3] (got " + formatNumber(s.solverTolerance) + ")");
    }
    if (s.maxIterations < 1)
    {
        throw InputError("maxIterations", "must be >= 1 (got " + std::to_string(s.maxIterations) + ")");
    }
    // A heater's or zone's own field, under its place in the list: "heaters[1].power".
    auto element = [](const char* list, std::size_t k, auto&& check)
    {
        try
        {
            check();
        }
        catch (const InputError& e)
        {
            throw InputError(std::string(list) + "[" + std::to_string(k) + "]." + e.field(), e.problem());
        }
    };
    for (std::size_t k = 0; k < s.heaters.size(); ++k)
    {
        element("heaters", k, [&] { validate(s.heaters[k]); });
    }
    for (std::size_t k = 0; k < s.hotAirZones.size(); ++k)
    {
        element("hotAirZones", k, [&] { validate(s.hotAirZones[k]); });
    }
}

ThermalModel::ThermalModel(const Lattice& lattice, const Material& material, Real thickness,
                           const ThermalSettings& settings)
    : m_material(material), m_settings(settings), m_geometry(lattice, thickness)
{
    validate(m_material);
    validate(m_settings);
    const std::size_t n = lattice.massCount();
    m_ends = lattice.springs.ends();
    m_class = lattice.springs.classes();
    const int layers = lattice.spec.layers;
    m_capacity.resize(n);
    const Real perArea = material.density * material.specificHeat * thickness / Real(layers);
    for (std::size_t i = 0; i < n; ++i)
    {
        m_capacity[i] = perArea * m_geometry.restArea()[i];
    }
    m_faces.resize(n);
    for (std::size_t i = 0; i < n; ++i)
    {
        const int layer = lattice.coord[i].layer;
        m_faces[i] = std::uint8_t((layer == 0 ? bottomFace : 0) | (layer == layers - 1 ? topFace : 0));
    }
    m_temperature.assign(n, settings.initialTemperature);
    m_held.assign(n, 0);
    computeWeights(lattice);
    buildPattern();
}

void ThermalModel::computeWeights(const Lattice& lattice)
{
    const std::size_t springCount = m_ends.size();
    m_weight.assign(springCount, Real(0));

    // Planar springs by their (lower, higher) mass indices, for lookup from the cells' edges.
    std::vector<std::tuple<Index, Index, std::size_t>> planar;
    std::size_t interLayerCount = 0;
    for (std::size_t s = 0; s < springCount; ++s)
    {
        const SpringEnds e = m_ends[s];
        if (m_class[s] == SpringClass::Planar)
        {
            planar.emplace_back(std::min(e.a, e.b), std::max(e.a, e.b), s);
        }
        else
        {
            ++interLayerCount;
        }
    }
    // The upper layers' area, shared equally among the inter-layer springs.
    Real upperArea = 0;
    for (std::size_t i = 0; i < lattice.massCount(); ++i)
    {
        if (lattice.coord[i].layer > 0)
        {
            upperArea += m_geometry.restArea()[i];
        }
    }
    m_interLayerArea = interLayerCount > 0 ? upperArea / Real(interLayerCount) : Real(0);
    std::sort(planar.begin(), planar.end());
    auto addWeight = [&](Index a, Index b, Real w)
    {
        const Index lo = std::min(a, b);
        const Index hi = std::max(a, b);
        const auto it = std::lower_bound(planar.begin(), planar.end(), std::make_tuple(lo, hi, std::size_t(0)));
        if (it != planar.end() && std::get<0>(*it) == lo && std::get<1>(*it) == hi)
        {
            m_weight[std::get<2>(*it)] += w;
        }
    };
    // Each triangle gives each of its edges half the cotangent of the angle facing it.
    const std::vector<Vec3>& x = lattice.position;
    auto addTriangle = [&](Index a, Index b, Index c)
    {
        addWeight(b, c, Real(0.5) * cotangent(x[a], x[b], x[c]));
        addWeight(c, a, Real(0.5) * cotangent(x[b], x[c], x[a]));
        addWeight(a, b, Real(0.5) * cotangent(x[c], x[a], x[b]));
    };
    const std::vector<Index>& cells = m_geometry.cells();
    const std::size_t corners = std::size_t(m_geometry.cornersPerCell());
    for (std::size_t start = 0; start < cells.size(); start += corners)
    {
        const Index* cell = cells.data() + start;
        addTriangle(cell[0], cell[1], cell[2]);
        if (corners == 4)
        {
            addTriangle(cell[0], cell[2], cell[3]);
        }
    }
    for (Real& w : m_weight)
    {
        w = std::max(w, Real(0));
    }
}

void ThermalModel::buildPattern()
{
    const std::size_t n = m_temperature.size();
    m_matrix.build(n, m_ends);
    m_rhs.setZero(Eigen::Index(n));
    m_solution.setZero(Eigen::Index(n));
    m_conductance.assign(m_ends.size(), Real(0));
}

void ThermalModel::setSettings(const ThermalSettings& settings)
{
    validate(settings);
    m_settings = settings;
}

void ThermalModel::setObstacleTemperatures(std::vector<Real> obstacleTemperature)
{
    for (std::size_t k = 0; k < obstacleTemperature.size(); ++k)
    {
        if (std::isnan(obstacleTemperature[k]))
        {
            continue; // at the air's temperature
        }
        if (!(obstacleTemperature[k] > 0) || !std::isfinite(obstacleTemperature[k]))
        {
            throw InputError("obstacleTemperature[" + std::to_string(k) + "]",
                             "must be above absolute zero (got " + formatNumber(obstacleTemperature[k]) + " K)");
        }
    }
    m_obstacleTemperature = std::move(obstacleTemperature);
}

void ThermalModel::holdTemperature(Index mass, Real temperature)
{
    if (!(temperature > 0) || !std::isfinite(temperature))
    {
        throw InputError("temperature", "must be above absolute zero (got " + formatNumber(temperature) + " K)");
    }
    m_held.at(mass) = 1;
    m_temperature[mass] = temperature;
}

void ThermalModel::releaseTemperature(Index mass)
{
    m_held.at(mass) = 0;
}

void ThermalModel::computeConductances()
{
    const Real conductivity = m_material.conductivity;
    const Real layers = Real(m_geometry.layerCount());
    const std::vector<Real>& h = m_geometry.thickness();
    const Real h0 = m_geometry.initialThickness();
    parallelFor(m_ends.size(), conductanceChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    for (std::size_t s = begin; s < end; ++s)
                    {
                        const SpringEnds e = m_ends[s];
                        const Real layerThickness = Real(0.5) * (h[e.a] + h[e.b]) / layers;
                        if (m_class[s] == SpringClass::Planar)
                        {
                            m_conductance[s] = conductivity * layerThickness * m_weight[s];
                        }
                        else
                        {
                            // The rest share, stretched as the sheet is: A / A0 = h0 / h at each end.
                            const Real stretch = Real(0.5) * (h0 / h[e.a] + h0 / h[e.b]);
                            m_conductance[s] = conductivity * m_interLayerArea * stretch / layerThickness;
                        }
                    }
                });
}

void ThermalModel::beginFrame(MassSpringSystem& /*system*/, StepContext& context, Real /*time*/, Real dt)
{
    m_frameDt = dt;
    context.temperature = m_temperature;
    context.thickness = &m_geometry;
}

void ThermalModel::endFrame(MassSpringSystem& system, StepContext& context, Real /*time*/)
{
    advance(system, m_frameDt, context.touchingObstacle);
}

void ThermalModel::advance(const MassSpringSystem& system, Real dt, std::span<const int> touchingObstacle)
{
    if (!(dt > 0) || !std::isfinite(dt))
    {
        throw InputError("dt", "must be a positive number of seconds (got " + formatNumber(dt) + ")");
    }
    requireSizes(system, touchingObstacle);
    const std::vector<Vec3>& x = system.particles.position;
    m_geometry.update(x);
    computeConductances();
    m_matrix.setZero();
    m_report = ThermalReport{};
    assembleExchanges(x, touchingObstacle, dt);
    assembleConduction();
    fixHeldTemperatures();
    solve(dt);
    reportFlows();
}

void ThermalModel::requireSizes(const MassSpringSystem& system, std::span<const int> touchingObstacle) const
{
    const std::size_t n = m_temperature.size();
    if (system.massCount() != n || system.springCount() != m_ends.size())
    {
        throw std::invalid_argument("ThermalModel: the system has " + std::to_string(system.massCount()) +
                                    " masses and " + std::to_string(system.springCount()) + " springs, the lattice " +
                                    std::to_string(n) + " and " + std::to_string(m_ends.size()));
    }
    if (!touchingObstacle.empty() && touchingObstacle.size() != n)
    {
        throw std::invalid_argument("ThermalModel: touching obstacles for " + std::to_string(touchingObstacle.size()) +
                                    " masses, expected " + std::to_string(n));
    }
}

ThermalModel::AirAt ThermalModel::airAt(const Vec3& x) const
{
    for (const HotAirZone& zone : m_settings.hotAirZones)
    {
        if (contains(zone, x))
        {
            return {zone.temperature, zone.heatTransfer};
        }
    }
    return {m_settings.airTemperature, m_settings.airHeatTransfer};
}

Real ThermalModel::absorbedHeat(std::size_t i, const Vec3& x, const Vec3& normal) const
{
    Real absorbed = 0;
    for (const RadiantHeater& heater : m_settings.heaters)
    {
        if (heater.power == 0)
        {
            continue; // switched off (a script's "heater" action): its view factor would only be multiplied by 0
        }
        if (m_faces[i] & topFace)
        {
            absorbed += heaterIrradiance(heater, x, normal);
        }
        if (m_faces[i] & bottomFace)
        {
            absorbed += heaterIrradiance(heater, x, -normal);
        }
    }
    // (absorptivity * area) first: recorded results depend on this order.
    return absorbed * (m_settings.absorptivity * m_geometry.area()[i]);
}

void ThermalModel::assembleExchanges(const std::vector<Vec3>& x, std::span<const int> touchingObstacle, Real dt)
{
    // Per mass: the exchange coefficient (W/K) and the heat it brings at T = 0, so that the flow is
    // source - coefficient * T; kept to report the flows after the solve.
    const std::size_t n = m_temperature.size();
    const std::vector<Real>& area = m_geometry.area();
    const std::vector<Vec3>& normal = m_geometry.normal();
    m_airCoefficient.assign(n, Real(0));
    m_airSource.assign(n, Real(0));
    m_contactCoefficient.assign(n, Real(0));
    m_contactSource.assign(n, Real(0));
    m_absorbed.assign(n, Real(0));
    // Each mass writes its own row, on the pool (the heaters' view factors are most of a heated step's thermal cost).
    parallelFor(n, massChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    for (std::size_t i = begin; i < end; ++i)
                    {
                        const Real diagonal = m_capacity[i] / dt;
                        m_matrix.value(m_matrix.diagonal(i)) += diagonal;
                        m_rhs[Eigen::Index(i)] = diagonal * m_temperature[i];
                        const int faceCount = ((m_faces[i] & bottomFace) ? 1 : 0) + ((m_faces[i] & topFace) ? 1 : 0);
                        if (faceCount > 0)
                        {
                            const AirAt air = airAt(x[i]);
                            m_airCoefficient[i] = air.heatTransfer * area[i] * Real(faceCount);
                            m_airSource[i] = m_airCoefficient[i] * air.temperature;
                            m_absorbed[i] = absorbedHeat(i, x[i], normal[i]);
                            m_rhs[Eigen::Index(i)] += m_absorbed[i];
                        }
                        if (!touchingObstacle.empty())
                        {
                            const int obstacle = touchingObstacle[i];
                            if (obstacle >= 0 && std::size_t(obstacle) < m_obstacleTemperature.size())
                            {
                                m_contactCoefficient[i] = m_settings.contactHeatTransfer * area[i];
                                const Real given = m_obstacleTemperature[std::size_t(obstacle)];
                                const Real surface = std::isnan(given) ? m_settings.airTemperature : given;
                                m_contactSource[i] = m_contactCoefficient[i] * surface;
                            }
                        }
                        m_matrix.value(m_matrix.diagonal(i)) += m_airCoefficient[i] + m_contactCoefficient[i];
                        m_rhs[Eigen::Index(i)] += m_airSource[i] + m_contactSource[i];
                    }
                });
    for (std::size_t i = 0; i < n; ++i) // in mass order, as the report's sum always is
    {
        if (!m_held[i])
        {
            m_report.heaterPower += m_absorbed[i];
        }
    }
}

void ThermalModel::assembleConduction()
{
    for (std::size_t s = 0; s < m_ends.size(); ++s)
    {
        const Index a = m_ends[s].a;
        const Index b = m_ends[s].b;
        const Real g = m_conductance[s];
        m_matrix.value(m_matrix.diagonal(a)) += g;
        m_matrix.value(m_matrix.diagonal(b)) += g;
        // A held neighbour is a known temperature: its coupling moves to the right-hand side, keeping the matrix
        // symmetric.
        if (m_held[a] || m_held[b])
        {
            if (!m_held[a])
            {
                m_rhs[Eigen::Index(a)] += g * m_temperature[b];
            }
            if (!m_held[b])
            {
                m_rhs[Eigen::Index(b)] += g * m_temperature[a];
            }
            continue;
        }
        m_matrix.value(m_matrix.ab(s)) -= g;
        m_matrix.value(m_matrix.ba(s)) -= g;
    }
}

void ThermalModel::fixHeldTemperatures()
{
    for (std::size_t i = 0; i < m_temperature.size(); ++i)
    {
        if (m_held[i])
        {
            m_matrix.value(m_matrix.diagonal(i)) = 1;
            m_rhs[Eigen::Index(i)] = m_temperature[i];
        }
        m_solution[Eigen::Index(i)] = m_temperature[i]; // the solve's first guess
    }
}

void ThermalModel::solve(Real dt)
{
    m_solver.setTolerance(m_settings.solverTolerance);
    m_solver.setMaxIterations(m_settings.maxIterations);
    m_solver.compute(m_matrix.matrix());
    m_solution = m_solver.solveWithGuess(m_rhs, m_solution);
    m_report.solverIterations = int(m_solver.iterations());
    m_report.solverResidual = m_solver.error();
    if (!m_solution.allFinite())
    {
        throw NumericalError("the thermal model diverged: a temperature is not finite after a step of " +
                             formatNumber(dt) + " s");
    }
}

void ThermalModel::reportFlows()
{
    for (std::size_t i = 0; i < m_temperature.size(); ++i)
    {
        const Real t = m_solution[Eigen::Index(i)];
        m_temperature[i] = t;
        if (m_held[i])
        {
            continue;
        }
        m_report.airPower += m_airSource[i] - m_airCoefficient[i] * t;
        m_report.contactPower += m_contactSource[i] - m_contactCoefficient[i] * t;
    }
}
} // namespace masse
