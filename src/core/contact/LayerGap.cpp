#include "core/contact/LayerGap.h"

#include "core/MassSpringSystem.h"
#include "core/StepContext.h"
#include "core/contact/ContactSolver.h"
#include "core/lattice/SpringTopology.h"
#include "core/material/Thickness.h"
#include "core/parallel/TaskPool.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace masse
{
namespace
{
/// The most a correction moves a mass across its cell's plane in one substep, in floor heights. A mass further across
/// than that has not been pressed too close to the layer beneath: its cell is tangled (folded over a corner, or turned
/// over by a throw). Put back in one substep it is thrown across distances the sheet never moves in a step, and on
/// the pressure tray (SaMM 33x2x25) such throws would grow a 1e-11 rounding difference between mirror halves into a
/// whole wall's difference; brought back over a few substeps it comes back as the sheet moves.
constexpr Real largestCorrection = 8;
constexpr Index notUpper = std::numeric_limits<Index>::max();
constexpr std::uint32_t noSlot = std::numeric_limits<std::uint32_t>::max();

/// The sum of a cell's values, one per corner. A square cell's corners are in grid order (row r: columns c, c + 1; row
/// r + 1: the same), summed as (v0 + v1) + (v2 + v3): mirrored across a column its corners swap in pairs (0 and 1, 2
/// and 3), across a row the pairs swap, and either way the sum is the same to the bit, so that a mirror-symmetric
/// sheet stays mirror-symmetric. A triangle's are summed in order.
template <class Value, class Of> Value cornerSum(const Index* corners, std::size_t count, Of of)
{
    if (count == 4)
    {
        return (of(corners[0]) + of(corners[1])) + (of(corners[2]) + of(corners[3]));
    }
    Value sum = of(corners[0]);
    for (std::size_t k = 1; k < count; ++k)
    {
        sum += of(corners[k]);
    }
    return sum;
}

/// Twice the cell's vector area: a square cell's from its diagonals, (v3 - v0) x (v2 - v1), which a mirror image
/// gives exactly mirrored; a triangle's (corners in their cyclic order) from two of its edges.
template <class Position> Vec3 cellNormal(const Index* corners, std::size_t count, Position at)
{
    if (count == 4)
    {
        return (at(corners[3]) - at(corners[0])).cross(at(corners[2]) - at(corners[1]));
    }
    return (at(corners[1]) - at(corners[0])).cross(at(corners[2]) - at(corners[0]));
}
} // namespace

LayerGap::LayerGap(const Lattice& lattice)
    : m_upperOf(lattice.massCount(), notUpper), m_squareSlots(lattice.spec.structure != Structure::TRiMM)
{
    const std::size_t n = lattice.massCount();
    std::vector<std::vector<Index>> below(n);
    for (const SpringEnds& spring : lattice.springs.ends())
    {
        const int layerA = lattice.coord[spring.a].layer;
        const int layerB = lattice.coord[spring.b].layer;
        if (layerA == layerB + 1)
        {
            below[spring.a].push_back(spring.b);
        }
        else if (layerB == layerA + 1)
        {
            below[spring.b].push_back(spring.a);
        }
    }
    m_cellOffset.push_back(0);
    std::vector<std::vector<std::uint32_t>> over(n);
    for (Index i = 0; i < Index(n); ++i)
    {
        std::vector<Index>& cell = below[i];
        if (cell.size() < 3)
        {
            continue;
        }
        const bool square = m_squareSlots;
        if (square && cell.size() != 4)
        {
            continue;
        }
        if (square)
        {
            // Grid order: the cell beneath upper mass (row r, column c) is rows r and r + 1, columns c and c + 1.
            const LatticeCoord& c = lattice.coord[i];
            cell = {lattice.index(c.layer - 1, c.row, c.column), lattice.index(c.layer - 1, c.row, c.column + 1),
                    lattice.index(c.layer - 1, c.row + 1, c.column),
                    lattice.index(c.layer - 1, c.row + 1, c.column + 1)};
        }
        else
        {
            // A triangle's corners in their cyclic order around it, seen from above (the lattice is built flat, its
            // layers stacked along y).
            Vec3 middle = Vec3::Zero();
            for (Index j : cell)
            {
                middle += lattice.position[j];
            }
            middle /= Real(cell.size());
            std::sort(cell.begin(), cell.end(),
                      [&](Index a, Index b)
                      {
                          const Vec3 da = lattice.position[a] - middle;
                          const Vec3 db = lattice.position[b] - middle;
                          return std::atan2(da.z(), da.x()) < std::atan2(db.z(), db.x());
                      });
            cell.resize(3);
        }
        auto rest = [&](Index j) -> Vec3 { return lattice.position[j]; };
        const Vec3 centroid = cornerSum<Vec3>(cell.data(), cell.size(), rest) / Real(cell.size());
        const Vec3 normal = cellNormal(cell.data(), cell.size(), rest);
        const Real restHeight = (lattice.position[i] - centroid).dot(normal.normalized());
        if (!(std::abs(restHeight) > 0))
        {
            continue;
        }
        m_upperOf[i] = Index(m_upper.size());
        for (std::size_t k = 0; k < cell.size(); ++k)
        {
            const Index j = cell[k];
            if (square)
            {
                // Slot 3 - k: the masses over a mass in grid order too (see cornerSum).
                over[j].resize(4, noSlot);
                over[j][3 - k] = std::uint32_t(m_upper.size());
            }
            else
            {
                over[j].push_back(std::uint32_t(m_upper.size()));
            }
            m_cell.push_back(j);
        }
        m_upper.push_back(i);
        m_cellOffset.push_back(m_cell.size());
        m_restHeight.push_back(std::abs(restHeight));
        m_restSide.push_back(restHeight > 0 ? Real(1) : Real(-1));
    }
    m_overOffset.push_back(0);
    for (const std::vector<std::uint32_t>& list : over)
    {
        m_over.insert(m_over.end(), list.begin(), list.end());
        m_overOffset.push_back(m_over.size());
    }
    m_positionShare.assign(m_upper.size(), 0);
    m_velocityShare.assign(m_upper.size(), 0);
    m_normal.assign(m_upper.size(), Vec3::Zero());
    m_upperYields.assign(m_upper.size(), 0);
}

Real LayerGap::height(const std::vector<Vec3>& x, Index u, Vec3& normal, Vec3& centroid) const
{
    const Index* corners = m_cell.data() + m_cellOffset[u];
    const std::size_t count = m_cellOffset[u + 1] - m_cellOffset[u];
    auto at = [&](Index j) -> Vec3 { return x[j]; };
    centroid = cornerSum<Vec3>(corners, count, at) / Real(count);
    normal = m_restSide[u] * cellNormal(corners, count, at);
    const Real length = normal.norm();
    if (!(length > 0))
    {
        normal = Vec3::Zero();
        return 0;
    }
    normal /= length;
    return (x[m_upper[u]] - centroid).dot(normal);
}

Real LayerGap::warp(const std::vector<Vec3>& x, Index u, const Vec3& normal) const
{
    const Index* corners = m_cell.data() + m_cellOffset[u];
    if (m_cellOffset[u + 1] - m_cellOffset[u] != 4)
    {
        return 0;
    }
    // The distance between the midpoints of a square cell's diagonals along its normal: nothing when the cell is flat.
    // Taken as (v0 + v3) - (v1 + v2), which a mirror image gives negated to the bit.
    return std::abs(((x[corners[0]] + x[corners[3]]) - (x[corners[1]] + x[corners[2]])).dot(normal)) / 2;
}

std::vector<Real> LayerGap::heightRatios(const std::vector<Vec3>& x) const
{
    std::vector<Real> ratios(x.size(), std::numeric_limits<Real>::quiet_NaN());
    for (Index u = 0; u < Index(m_upper.size()); ++u)
    {
        Vec3 normal;
        Vec3 centroid;
        ratios[m_upper[u]] = height(x, u, normal, centroid) / m_restHeight[u];
    }
    return ratios;
}

void LayerGap::afterImplicitSolve(MassSpringSystem& system, StepContext& context, Real h, Real /*time*/)
{
    correct(system, context, h);
}

void LayerGap::afterSubstep(MassSpringSystem& system, StepContext& context, Real /*h*/, Real /*time*/)
{
    correct(system, context, 0);
}

void LayerGap::correct(MassSpringSystem& system, const StepContext& context, Real solveStep)
{
    Particles& p = system.particles;
    const std::span<const int> touching = context.touchingObstacle;
    const SheetThickness* thickness = context.thickness;
    auto touches = [&](Index j) { return !touching.empty() && touching[j] >= 0; };
    // A mass held by the mould or the clamp does not give way to the layer above it.
    auto weight = [&](Index j) -> Real { return touches(j) ? Real(0) : p.inverseMass[j]; };

    // Each constraint from the same positions and velocities.
    parallelFor(
        m_upper.size(), massChunkSize,
        [&](std::size_t begin, std::size_t end)
        {
            for (std::size_t u = begin; u < end; ++u)
            {
                m_positionShare[u] = 0;
                m_velocityShare[u] = 0;
                m_upperYields[u] = 0;
                const Index i = m_upper[u];
                Vec3 normal;
                Vec3 centroid;
                const Real gap = height(p.position, Index(u), normal, centroid);
                const Real ratio =
                    thickness ? std::min(Real(1), thickness->thickness()[i] / thickness->initialThickness()) : Real(1);
                // A cell that folds over a mould's rim or into its corner (its corners on the flange and on
                // the floor) has no plane to stand over: its centroid hangs in the air between them, and a
                // mass lying on the mould beside it would be thrown the depth of the wall. The floor falls
                // with the cell's warp, to nothing at a warp of the rest height: smoothly, as an on-off rule
                // would flick a mass over a cell near the bound back and forth.
                const Real flatness = std::max(Real(0), 1 - warp(p.position, Index(u), normal) / m_restHeight[u]);
                const Real floorHeight = m_restHeight[u] * ratio * flatness;
                const Real deficit = std::min(floorHeight - gap, largestCorrection * floorHeight);
                if (!(deficit > 0) || normal.isZero())
                {
                    continue;
                }
                const Index* corners = m_cell.data() + m_cellOffset[u];
                const std::size_t count = m_cellOffset[u + 1] - m_cellOffset[u];
                const Real k = Real(count);
                const Real cornerWeights = cornerSum<Real>(corners, count, weight);
                const Vec3 cornerVelocity =
                    cornerSum<Vec3>(corners, count, [&](Index j) -> Vec3 { return p.velocity[j]; });
                bool cellTouches = true;
                bool cornerTouches = false;
                for (std::size_t c = 0; c < count; ++c)
                {
                    cellTouches = cellTouches && touches(corners[c]);
                    cornerTouches = cornerTouches || touches(corners[c]);
                }
                // An upper mass on an obstacle gives way, and moves back alone, over a cell on the obstacle, and over
                // a cell partly on it once the mass has gone through the cell (gap < 0): such a cell is draped over a
                // mould's rim, some corners on the flange and some over the cavity, and the correction would fall on
                // its free corners, k times the deficit on a lone one, along a normal that a cell tipped over the rim
                // may point the wrong way: on the pressure tray at 128x2x128 that throws a lower mass at the rim 9 mm,
                // to 64 m/s, in one substep, and such throws split every frame into its most solves until the run
                // diverges.
                m_upperYields[u] = touches(i) && (cellTouches || (cornerTouches && gap < 0));
                const Real upperWeight = m_upperYields[u] ? p.inverseMass[i] : weight(i);
                const Real weights = upperWeight + (m_upperYields[u] ? Real(0) : cornerWeights / (k * k));
                if (!(weights > 0))
                {
                    continue;
                }
                m_normal[u] = normal;
                m_positionShare[u] = deficit / weights;
                // The approach is taken out of the velocity. After the implicit solve only as much of it as the
                // solve closed the gap by, deficit / h, as position-based dynamics sets v = (x - x0) / h: a deficit
                // older than the solve (left by a longer step before, or by a mass thrown across its cell) is put
                // right in position only: turned into velocity, a deficit of 8 floors that a short solve finds would
                // throw the mass out at 8 floors per solve, 10 m/s in the vacuum cup at 64x2x64 in solves of 1.25 ms.
                const Real approach = (p.velocity[i] - cornerVelocity / k).dot(normal);
                const Real removed = approach < 0 ? -approach : Real(0);
                m_velocityShare[u] = (solveStep > 0 ? std::min(removed, deficit / solveStep) : removed) / weights;
            }
        });

    // Each mass gathers its corrections: its own constraint's, then those of the masses over it, in a fixed order.
    // After the substep's projection (solveStep 0), a mass the floor pushes toward an obstacle it does not touch yet
    // (a lower mass under an upper one the plug holds) is kept in front of it: the projection has been, and the next
    // frame would find the mass behind the surface.
    const bool afterProjection = solveStep == 0;
    std::vector<std::size_t> movedPerChunk(chunkCount(p.size(), massChunkSize), 0);
    parallelFor(p.size(), massChunkSize,
                [&](std::size_t begin, std::size_t end)
                {
                    std::size_t moved = 0;
                    for (std::size_t j = begin; j < end; ++j)
                    {
                        const Index own = m_upperOf[j];
                        const bool yields = own != notUpper && m_upperYields[own];
                        const Real w = yields ? p.inverseMass[j] : weight(Index(j));
                        if (w == 0)
                        {
                            continue;
                        }
                        Vec3 dx = Vec3::Zero();
                        Vec3 dv = Vec3::Zero();
                        bool corrected = false;
                        if (own != notUpper && m_positionShare[own] > 0)
                        {
                            dx += m_positionShare[own] * m_normal[own];
                            dv += m_velocityShare[own] * m_normal[own];
                            corrected = true;
                        }
                        // The masses over j, in their slots' order; a square lattice's four summed as a cell's
                        // corners are (cornerSum).
                        const std::size_t slots = m_overOffset[j + 1] - m_overOffset[j];
                        Vec3 overPosition[4] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
                        Vec3 overVelocity[4] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
                        for (std::size_t o = 0; o < slots; ++o)
                        {
                            const std::uint32_t u = m_over[m_overOffset[j] + o];
                            if (u == noSlot || !(m_positionShare[u] > 0) || m_upperYields[u])
                            {
                                continue;
                            }
                            const Real k = Real(m_cellOffset[u + 1] - m_cellOffset[u]);
                            const Vec3 position = (m_positionShare[u] / k) * m_normal[u];
                            const Vec3 velocity = (m_velocityShare[u] / k) * m_normal[u];
                            corrected = true;
                            if (m_squareSlots)
                            {
                                overPosition[o] = position;
                                overVelocity[o] = velocity;
                            }
                            else
                            {
                                dx -= position;
                                dv -= velocity;
                            }
                        }
                        if (m_squareSlots && slots == 4)
                        {
                            dx -= (overPosition[0] + overPosition[1]) + (overPosition[2] + overPosition[3]);
                            dv -= (overVelocity[0] + overVelocity[1]) + (overVelocity[2] + overVelocity[3]);
                        }
                        if (corrected)
                        {
                            p.position[j] += w * dx;
                            p.velocity[j] += w * dv;
                            if (afterProjection && m_contact)
                            {
                                m_contact->keepInFront(Index(j), p.position[j], p.velocity[j]);
                            }
                            ++moved;
                            if (yields && m_contact)
                            {
                                m_contact->release(Index(j));
                            }
                        }
                    }
                    movedPerChunk[begin / massChunkSize] = moved;
                });
    m_lastCorrected = 0;
    for (std::size_t moved : movedPerChunk)
    {
        m_lastCorrected += moved;
    }
}
} // namespace masse
