/// Square lattices: the 2D square grid (paper figure 4), SaMM (figure 5) and SLaMM (figure 6).
///
/// Layer l has (NX - l) x (NZ - l) masses on a grid of spacing hx = width / (NX - 1), hz = depth / (NZ - 1), shifted by
/// half a cell per layer, so every mass of layer l + 1 sits over the centre of a square of layer l.
///
/// One cell seen from above (z down the page, x across), bottom layer o, upper layer *:
///
///     o-----o        Planar springs join grid neighbours along x and z (the lines) in every layer.
///     |\   /|        Inter-layer springs (SaMM, SLaMM) join each upper mass * to the four corners of the square
///     | \ / |        below it (the slanted lines; in 3D they rise from the corners to *).
///     |  *  |
///     | / \ |        SLaMM adds one planar brace per square of every layer, from the near-left corner
///     |/   \|        (row r, column c) to the far-right corner (row r + 1, column c + 1), so that the square cannot
///     o-----o        shear into a rhombus.
///
/// Counts for an N x 2 x N SaMM sheet: masses N^2 + (N-1)^2; springs 2N(N-1) + 2(N-1)(N-2) + 4(N-1)^2.

#include "core/lattice/Lattice.h"

namespace masse
{
namespace
{
Real distance(const std::vector<Vec3>& x, Index a, Index b)
{
    return (x[a] - x[b]).norm();
}
} // namespace

void buildSquareLattice(Lattice& lattice)
{
    const LatticeSpec& spec = lattice.spec;
    const Real hx = (spec.maxCorner.x() - spec.minCorner.x()) / Real(spec.countX - 1);
    const Real hz = (spec.maxCorner.z() - spec.minCorner.z()) / Real(spec.countZ - 1);
    const Real hy = spec.layers > 1 ? (spec.maxCorner.y() - spec.minCorner.y()) / Real(spec.layers - 1) : Real(0);
    lattice.spacingX = hx;
    lattice.spacingZ = hz;

    for (int layer = 0; layer < spec.layers; ++layer)
    {
        lattice.layerStart.push_back(Index(lattice.position.size()));
        const Real shift = Real(0.5) * Real(layer);
        for (int row = 0; row < lattice.layerCountZ(layer); ++row)
        {
            for (int column = 0; column < lattice.layerCountX(layer); ++column)
            {
                lattice.position.emplace_back(spec.minCorner.x() + (Real(column) + shift) * hx,
                                              spec.minCorner.y() + Real(layer) * hy,
                                              spec.minCorner.z() + (Real(row) + shift) * hz);
                lattice.coord.push_back({layer, row, column});
            }
        }
    }
    lattice.layerStart.push_back(Index(lattice.position.size()));

    const bool braced = spec.structure == Structure::SLaMM;
    SpringSet& springs = lattice.springs;
    const std::vector<Vec3>& x = lattice.position;
    auto link = [&](Index a, Index b, SpringClass cls) { springs.add(a, b, distance(x, a, b), cls); };

    // Springs are emitted row by row, and within a row direction by direction (along x, along z, the brace; then the
    // inter-layer springs, one corner at a time), so that each direction of a row is a run of consecutive springs
    // joining consecutive masses: the banded force kernel (SpringRowPlan.h) then loads them contiguously.
    for (int layer = 0; layer < spec.layers; ++layer)
    {
        const int nx = lattice.layerCountX(layer);
        const int nz = lattice.layerCountZ(layer);
        for (int row = 0; row < nz; ++row)
        {
            for (int column = 0; column + 1 < nx; ++column)
            {
                link(lattice.index(layer, row, column), lattice.index(layer, row, column + 1), SpringClass::Planar);
            }
            if (row + 1 == nz)
            {
                continue;
            }
            for (int column = 0; column < nx; ++column)
            {
                link(lattice.index(layer, row, column), lattice.index(layer, row + 1, column), SpringClass::Planar);
            }
            for (int column = 0; braced && column + 1 < nx; ++column)
            {
                link(lattice.index(layer, row, column), lattice.index(layer, row + 1, column + 1), SpringClass::Planar);
            }
        }
        if (layer == 0)
        {
            continue;
        }
        // Each mass of this layer sits over the square (row, column)..(row + 1, column + 1) of the layer below.
        for (int row = 0; row < nz; ++row)
        {
            const int corners[4][2] = {{0, 0}, {0, 1}, {1, 0}, {1, 1}}; // (row, column) offsets below the upper mass
            for (const auto& corner : corners)
            {
                for (int column = 0; column < nx; ++column)
                {
                    link(lattice.index(layer, row, column),
                         lattice.index(layer - 1, row + corner[0], column + corner[1]), SpringClass::InterLayer);
                }
            }
        }
    }
}
} // namespace masse
