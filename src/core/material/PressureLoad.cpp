#include "core/material/PressureLoad.h"

#include "core/Format.h"
#include "core/InputError.h"
#include "core/parallel/TaskPool.h"

#include <cmath>
#include <cstdint>
#include <string>
#include <utility>

namespace masse
{
PressureSchedule::PressureSchedule(std::vector<PressureKey> keys) : m_keys(std::move(keys))
{
    for (std::size_t k = 0; k < m_keys.size(); ++k)
    {
        const std::string key = "keys[" + std::to_string(k) + "]";
        if (!std::isfinite(m_keys[k].time) || m_keys[k].time < 0)
        {
            throw InputError(key + ".time", "must be a finite number of seconds >= 0");
        }
        if (!std::isfinite(m_keys[k].pressure))
        {
            throw InputError(key + ".pressure", "must be a finite number of Pa");
        }
        if (k > 0 && !(m_keys[k].time > m_keys[k - 1].time))
        {
            throw InputError(key + ".time", "the keys must be in increasing time (" + formatNumber(m_keys[k].time) +
                                                " s follows " + formatNumber(m_keys[k - 1].time) + " s)");
        }
    }
}

Real PressureSchedule::at(Real time) const
{
    if (m_keys.empty())
    {
        return 0;
    }
    if (time <= m_keys.front().time)
    {
        return m_keys.front().pressure;
    }
    for (std::size_t k = 1; k < m_keys.size(); ++k)
    {
        if (time < m_keys[k].time)
        {
            const PressureKey& a = m_keys[k - 1];
            const PressureKey& b = m_keys[k];
            const Real s = (time - a.time) / (b.time - a.time);
            return a.pressure + s * (b.pressure - a.pressure);
        }
    }
    return m_keys.back().pressure;
}

namespace
{
/// Triangles per chunk of the load's pass over the surface: some hundred kilobytes of positions and shares.
constexpr std::size_t trianglesPerChunk = 8192;

/// The four triangles of each square of a square lattice's layer: the split along the diagonal from (row, column) to
/// (row + 1, column + 1) and the split along the other, each wound so its normal points to +y at rest.
std::vector<Triangle> squareTrianglesOfBothSplits(const Lattice& lattice, int layer)
{
    std::vector<Triangle> triangles;
    const int nx = lattice.layerCountX(layer);
    const int nz = lattice.layerCountZ(layer);
    for (int row = 0; row + 1 < nz; ++row)
    {
        for (int column = 0; column + 1 < nx; ++column)
        {
            const Index a = lattice.index(layer, row, column);
            const Index b = lattice.index(layer, row, column + 1);
            const Index c = lattice.index(layer, row + 1, column + 1);
            const Index d = lattice.index(layer, row + 1, column);
            for (Triangle t : {Triangle{a, b, c}, Triangle{a, c, d}, Triangle{a, b, d}, Triangle{b, c, d}})
            {
                const Vec3& first = lattice.position[t[0]];
                if ((lattice.position[t[1]] - first).cross(lattice.position[t[2]] - first).y() < 0)
                {
                    std::swap(t[1], t[2]);
                }
                triangles.push_back(t);
            }
        }
    }
    return triangles;
}
} // namespace

PressureLoad::PressureLoad(const Lattice& lattice, PressureSchedule schedule)
    : m_schedule(std::move(schedule)), m_layers(lattice.spec.layers), m_below(lattice.massCount()),
      m_applied(lattice.massCount(), Vec3::Zero()), m_next(lattice.massCount(), Vec3::Zero())
{
    const int layers = lattice.spec.layers;
    for (int layer = 0; layer < layers; ++layer)
    {
        if (lattice.spec.structure == Structure::TRiMM)
        {
            for (const Triangle& t : layerTriangles(lattice, layer))
            {
                m_triangles.push_back(t);
                m_triangleShare.push_back(Real(1) / Real(layers));
                m_bottom.push_back(layer == 0 ? 1 : 0);
            }
            continue;
        }
        // A square is loaded as both of its splits into two triangles, each at half weight: every corner of a flat
        // square then takes a quarter of its load, so the load is as mirror-symmetric as the lattice. (One split
        // would give the two corners on its diagonal twice the load of the other two.)
        for (const Triangle& t : squareTrianglesOfBothSplits(lattice, layer))
        {
            m_triangles.push_back(t);
            m_triangleShare.push_back(Real(0.5) / Real(layers));
            m_bottom.push_back(layer == 0 ? 1 : 0);
        }
    }
    // Each mass's triangles, in increasing order (the gather's order in computeLoad).
    m_cornerOffsets.assign(lattice.massCount() + 1, 0);
    for (const Triangle& t : m_triangles)
    {
        for (const Index corner : t)
        {
            ++m_cornerOffsets[corner + 1];
        }
    }
    for (std::size_t i = 0; i < lattice.massCount(); ++i)
    {
        m_cornerOffsets[i + 1] += m_cornerOffsets[i];
    }
    m_cornerTriangles.resize(m_cornerOffsets.back());
    std::vector<std::size_t> filled(m_cornerOffsets.begin(), m_cornerOffsets.end() - 1);
    for (std::size_t k = 0; k < m_triangles.size(); ++k)
    {
        for (const Index corner : m_triangles[k])
        {
            m_cornerTriangles[filled[corner]++] = std::uint32_t(k);
        }
    }
    std::vector<int> layerOf(lattice.massCount(), 0);
    for (std::size_t i = 0; i < lattice.massCount(); ++i)
    {
        layerOf[i] = lattice.coord[i].layer;
    }
    for (std::size_t s = 0; s < lattice.springCount(); ++s)
    {
        if (lattice.springs.classes()[s] != SpringClass::InterLayer)
        {
            continue;
        }
        const Index a = lattice.springs.ends()[s].a;
        const Index b = lattice.springs.ends()[s].b;
        if (layerOf[a] == layerOf[b] + 1)
        {
            m_below[a].push_back(b);
        }
        else if (layerOf[b] == layerOf[a] + 1)
        {
            m_below[b].push_back(a);
        }
    }
}

void PressureLoad::computeLoad(const std::vector<Vec3>& x, Real pressure, std::vector<Vec3>& force) const
{
    // Each triangle's share on the pool, then each mass gathers its triangles' in increasing order, the order of a
    // scatter triangle by triangle: the same bits at any thread count. Only the sealed area is summed in order after.
    const bool sealing = m_sealed.size() == x.size();
    m_share.resize(m_triangles.size());
    m_sealedPart.resize(m_triangles.size());
    parallelFor(m_triangles.size(), trianglesPerChunk,
                [&](std::size_t begin, std::size_t end)
                {
                    for (std::size_t k = begin; k < end; ++k)
                    {
                        const Triangle& t = m_triangles[k];
                        const Vec3 doubleArea = (x[t[1]] - x[t[0]]).cross(x[t[2]] - x[t[0]]);
                        m_sealedPart[k] = -1; // not sealed: it carries its share
                        if (sealing && m_sealed[t[0]] && m_sealed[t[1]] && m_sealed[t[2]])
                        {
                            // Weighted as the load is: a square's four triangles at half weight make up its area once.
                            m_sealedPart[k] = m_bottom[k]
                                                  ? Real(0.5) * m_triangleShare[k] * Real(m_layers) * doubleArea.norm()
                                                  : Real(0);
                            continue;
                        }
                        // -(p / L) A n / 3 per corner, with A n = (b - a) x (c - a) / 2 (triangles are wound so n is
                        // the top side).
                        m_share[k] = (-pressure * m_triangleShare[k] / Real(6)) * doubleArea;
                    }
                });
    force.resize(x.size());
    parallelFor(x.size(), massChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    for (std::size_t i = begin; i < end; ++i)
                    {
                        Vec3 sum = Vec3::Zero();
                        for (std::size_t c = m_cornerOffsets[i]; c < m_cornerOffsets[i + 1]; ++c)
                        {
                            const std::size_t k = m_cornerTriangles[c];
                            if (m_sealedPart[k] < 0)
                            {
                                sum += m_share[k];
                            }
                        }
                        force[i] = sum;
                    }
                });
    m_sealedArea = 0;
    if (sealing)
    {
        for (const Real part : m_sealedPart)
        {
            if (!(part < 0))
            {
                m_sealedArea += part;
            }
        }
    }
}

void PressureLoad::apply(MassSpringSystem& system, Real pressure)
{
    Particles& p = system.particles;
    m_pressure = pressure;
    computeLoad(p.position, pressure, m_next);
    parallelFor(p.size(), massChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    for (std::size_t i = begin; i < end; ++i)
                    {
                        p.externalForce[i] += m_next[i] - m_applied[i];
                    }
                });
    m_applied.swap(m_next);
}

void PressureLoad::beginFrame(MassSpringSystem& system, StepContext& /*context*/, Real time, Real dt)
{
    apply(system, m_schedule.at(time + dt));
}

void PressureLoad::afterSubstep(MassSpringSystem& system, StepContext& /*context*/, Real h, Real time)
{
    apply(system, m_schedule.at(time + h));
}

void PressureLoad::endFrame(MassSpringSystem& /*system*/, StepContext& context, Real /*time*/)
{
    const std::span<const int> touching = context.touchingObstacle;
    if (!m_sealing || touching.empty())
    {
        m_sealed.clear();
        return;
    }
    m_sealed.resize(touching.size());
    // Masses are numbered layer by layer from the bottom, so the layer below is decided before the one above.
    for (std::size_t i = 0; i < m_sealed.size(); ++i)
    {
        if (m_below[i].empty())
        {
            m_sealed[i] = touching[i] >= 0 ? 1 : 0;
            continue;
        }
        bool sealed = true;
        for (Index j : m_below[i])
        {
            sealed = sealed && m_sealed[j];
        }
        m_sealed[i] = sealed ? 1 : 0;
    }
}
} // namespace masse
