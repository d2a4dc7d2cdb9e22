#include "core/material/Thickness.h"

#include "core/Format.h"
#include "core/InputError.h"
#include "core/parallel/TaskPool.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <string>

namespace masse
{
namespace
{
/// Area below which a mass's area counts as collapsed: its thickness is capped at h0 / this fraction, not infinity.
constexpr Real collapsedAreaFraction = 1e-12;

/// The triangles of TRiMM layer `layer`, as in TriangularLattice.cpp: between rows r and r + 1, an "up" triangle
/// with two corners on row r (the one an upper mass sits over) and a "down" one with two corners on row r + 1.
void appendTriangles(const Lattice& lattice, int layer, std::vector<Index>& cells)
{
    const int nx = lattice.layerCountX(layer);
    const int nz = lattice.layerCountZ(layer);
    for (int row = 0; row + 1 < nz; ++row)
    {
        // After an even row the next row is shifted half a spacing to +x, after an odd row to -x.
        const bool nextShiftedRight = row % 2 == 0;
        for (int column = 0; column + 1 < nx; ++column)
        {
            const Index a = lattice.index(layer, row, column);
            const Index b = lattice.index(layer, row, column + 1);
            const Index c = lattice.index(layer, row + 1, column);
            const Index d = lattice.index(layer, row + 1, column + 1);
            const std::array<Index, 6> both =
                nextShiftedRight ? std::array<Index, 6>{a, b, c, c, d, b} : std::array<Index, 6>{a, b, d, c, d, a};
            cells.insert(cells.end(), both.begin(), both.end());
        }
    }
}

void appendSquares(const Lattice& lattice, int layer, std::vector<Index>& cells)
{
    const int nx = lattice.layerCountX(layer);
    const int nz = lattice.layerCountZ(layer);
    for (int row = 0; row + 1 < nz; ++row)
    {
        for (int column = 0; column + 1 < nx; ++column)
        {
            cells.push_back(lattice.index(layer, row, column));
            cells.push_back(lattice.index(layer, row, column + 1));
            cells.push_back(lattice.index(layer, row + 1, column + 1));
            cells.push_back(lattice.index(layer, row + 1, column));
        }
    }
}

/// Twice the vector area of a triangle.
Vec3 doubleVectorArea(const Vec3& a, const Vec3& b, const Vec3& c)
{
    return (b - a).cross(c - a);
}
} // namespace

SheetThickness::SheetThickness(const Lattice& lattice, Real thickness) : m_initialThickness(thickness)
{
    if (!(thickness > 0) || !std::isfinite(thickness))
    {
        throw InputError("thickness", "must be a positive number of m (got " + formatNumber(thickness) + ")");
    }
    const bool triangular = lattice.spec.structure == Structure::TRiMM;
    m_cornersPerCell = triangular ? 3 : 4;
    m_layerCount = lattice.spec.layers;
    for (int layer = 0; layer < m_layerCount; ++layer)
    {
        m_layerCellStart.push_back(m_cells.size() / std::size_t(m_cornersPerCell));
        if (triangular)
        {
            appendTriangles(lattice, layer, m_cells);
        }
        else
        {
            appendSquares(lattice, layer, m_cells);
        }
    }
    m_layerCellStart.push_back(m_cells.size() / std::size_t(m_cornersPerCell));
    // Orient every cell counter-clockwise seen from +y, so that normals point to the sheet's top side.
    const std::size_t corners = std::size_t(m_cornersPerCell);
    for (std::size_t start = 0; start < m_cells.size(); start += corners)
    {
        Index* cell = m_cells.data() + start;
        const std::vector<Vec3>& x = lattice.position;
        const Vec3 normal = doubleVectorArea(x[cell[0]], x[cell[1]], x[cell[2]]);
        if (normal.y() < 0)
        {
            std::reverse(cell + 1, cell + corners);
        }
    }

    const std::size_t n = lattice.massCount();
    m_layer.resize(n);
    for (std::size_t i = 0; i < n; ++i)
    {
        m_layer[i] = lattice.coord[i].layer;
    }
    std::vector<Vec3> restVectorArea;
    accumulate(lattice.position, m_restArea, restVectorArea);
    m_cellless.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i)
    {
        if (m_restArea[i] == 0)
        {
            m_cellless[i] = 1;
            m_restArea[i] = lattice.spacingX * lattice.spacingZ;
        }
    }
    m_restVolume = 0;
    for (std::size_t i = 0; i < n; ++i)
    {
        if (m_layer[i] == 0)
        {
            m_restVolume += thickness * m_restArea[i];
        }
    }
    update(lattice.position);
}

void SheetThickness::accumulate(const std::vector<Vec3>& x, std::vector<Real>& area,
                                std::vector<Vec3>& vectorArea) const
{
    area.assign(m_layer.size(), Real(0));
    vectorArea.assign(m_layer.size(), Vec3::Zero());
    const std::size_t corners = std::size_t(m_cornersPerCell);
    // A layer's cells have their corners in that layer alone: the layers add to disjoint masses, each in its cells'
    // order, so they run at once and every sum has the same bits at any thread count.
    parallelFor(m_layerCellStart.size() - 1, 1,
                [&](std::size_t firstLayer, std::size_t endLayer)
                {
                    for (std::size_t cellIndex = m_layerCellStart[firstLayer]; cellIndex < m_layerCellStart[endLayer];
                         ++cellIndex)
                    {
                        const Index* cell = m_cells.data() + cellIndex * corners;
                        Vec3 doubled;
                        Real size;
                        if (corners == 3)
                        {
                            doubled = doubleVectorArea(x[cell[0]], x[cell[1]], x[cell[2]]);
                            size = Real(0.5) * doubled.norm();
                        }
                        else
                        {
                            // A bent square's area is the mean of its two splits into triangles (along either
                            // diagonal), so that a square and its mirror image have the same area and a
                            // mirror-symmetric sheet a mirror-symmetric thickness field (Forming.MirrorSymmetric*).
                            // The vector area is the same for either split.
                            const Vec3 first = doubleVectorArea(x[cell[0]], x[cell[1]], x[cell[2]]);
                            const Vec3 second = doubleVectorArea(x[cell[0]], x[cell[2]], x[cell[3]]);
                            const Vec3 third = doubleVectorArea(x[cell[0]], x[cell[1]], x[cell[3]]);
                            const Vec3 fourth = doubleVectorArea(x[cell[1]], x[cell[2]], x[cell[3]]);
                            doubled = first + second;
                            size = Real(0.25) * ((first.norm() + second.norm()) + (third.norm() + fourth.norm()));
                        }
                        const Real share = size / Real(corners);
                        const Vec3 vectorShare = doubled * (Real(0.5) / Real(corners));
                        for (std::size_t k = 0; k < corners; ++k)
                        {
                            area[cell[k]] += share;
                            vectorArea[cell[k]] += vectorShare;
                        }
                    }
                });
}

void SheetThickness::update(const std::vector<Vec3>& x)
{
    static_assert(sizeof(Vec3) == 3 * sizeof(Real), "positions are compared as their bytes");
    if (x.size() == m_updatedAt.size() && std::memcmp(x.data(), m_updatedAt.data(), x.size() * sizeof(Vec3)) == 0)
    {
        return; // the same bits give the same areas, normals and thicknesses
    }
    m_updatedAt = x;
    accumulate(x, m_area, m_vectorArea);
    const std::size_t n = m_layer.size();
    m_thickness.resize(n);
    m_normal.resize(n);
    parallelFor(n, massChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    for (std::size_t i = begin; i < end; ++i)
                    {
                        const Real rest = m_restArea[i];
                        if (m_cellless[i])
                        {
                            m_area[i] = rest;
                        }
                        const Real current = std::max(m_area[i], collapsedAreaFraction * rest);
                        m_thickness[i] = m_initialThickness * rest / current;
                        const Real length = m_vectorArea[i].norm();
                        m_normal[i] = length > 0 ? Vec3(m_vectorArea[i] / length) : Vec3(Vec3::UnitY());
                    }
                });
    // The volume and the thinnest mass in mass order (a sum's bits depend on its order; the first thinnest wins).
    m_minimumThickness = std::numeric_limits<Real>::infinity();
    m_thinnestMass = 0;
    m_volume = 0;
    for (std::size_t i = 0; i < n; ++i)
    {
        if (m_layer[i] == 0)
        {
            m_volume += m_thickness[i] * m_area[i];
        }
        if (m_thickness[i] < m_minimumThickness)
        {
            m_minimumThickness = m_thickness[i];
            m_thinnestMass = Index(i);
        }
    }
}
} // namespace masse
