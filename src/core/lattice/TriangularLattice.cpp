/// TRiMM, the triangular lattice (paper figure 7).
///
/// Each layer is a triangular lattice: rows along x, alternate rows shifted by half a spacing, so every interior mass
/// has six planar neighbours. Seen from above (z down the page), bottom layer o, upper layer *:
///
///     row 0   o-------o-------o          Planar springs: along each row, and from each mass to the two nearest
///              \  *  / \  *  / \         masses of the next row (the zig-zag), making triangles.
///     row 1     o-------o-------o
///              /  *  \ /  *  \ /         Upper layer: one mass over the centroid of every triangle that has two
///     row 2   o-------o-------o          corners on row r and its apex on row r + 1; it is joined to those three
///                                        corners by inter-layer springs. These centroids form the same lattice
///                                        again, (NX - 1) x (NZ - 1), shifted by half a spacing in x and a third of
///                                        a row in z, with its own planar springs.
///
/// Spacings: hx = width / (NX - 1/2), so that shifted rows still fit the sheet box; hz = depth / (NZ - 1).
/// Layer l, row r, column c is at x = x0 + (c + ((r mod 2) + l) / 2) hx, z = z0 + (r + l / 3) hz.
///
/// An N x 2 x N sheet has N^2 + (N-1)^2 masses and (3N^2 - 4N + 1) + (3(N-1)^2 - 4(N-1) + 1) + 3(N-1)^2
/// = 9N^2 - 20N + 12 springs: exactly the paper's Table 2 (3x2x3: 13 masses, 33 springs; 12x2x12: 265, 1068).

#include "core/lattice/Lattice.h"

namespace masse
{
void buildTriangularLattice(Lattice& lattice)
{
    const LatticeSpec& spec = lattice.spec;
    const Real hx = (spec.maxCorner.x() - spec.minCorner.x()) / (Real(spec.countX) - Real(0.5));
    const Real hz = (spec.maxCorner.z() - spec.minCorner.z()) / Real(spec.countZ - 1);
    const Real hy = (spec.maxCorner.y() - spec.minCorner.y()) / Real(spec.layers - 1);
    lattice.spacingX = hx;
    lattice.spacingZ = hz;

    for (int layer = 0; layer < spec.layers; ++layer)
    {
        lattice.layerStart.push_back(Index(lattice.position.size()));
        for (int row = 0; row < lattice.layerCountZ(layer); ++row)
        {
            const Real shift = Real(0.5) * Real((row % 2) + layer);
            for (int column = 0; column < lattice.layerCountX(layer); ++column)
            {
                lattice.position.emplace_back(spec.minCorner.x() + (Real(column) + shift) * hx,
                                              spec.minCorner.y() + Real(layer) * hy,
                                              spec.minCorner.z() + (Real(row) + Real(layer) / Real(3)) * hz);
                lattice.coord.push_back({layer, row, column});
            }
        }
    }
    lattice.layerStart.push_back(Index(lattice.position.size()));

    SpringSet& springs = lattice.springs;
    const std::vector<Vec3>& x = lattice.position;
    auto link = [&](Index a, Index b, SpringClass cls) { springs.add(a, b, (x[a] - x[b]).norm(), cls); };

    // Springs are emitted row by row, and within a row direction by direction (along the row, to the next row's mass
    // in the same column, the zig-zag diagonal; then the inter-layer springs, one direction at a time), so that each
    // direction of a row is a run of consecutive springs joining consecutive masses: the banded force kernel
    // (SpringRowPlan.h) then loads them contiguously.
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
            // In every layer, the row after an even row is shifted half a spacing to +x, after an odd row to -x.
            const int diagonalOffset = row % 2 == 0 ? -1 : 1;
            for (int column = 0; column < nx; ++column)
            {
                const int diagonal = column + diagonalOffset;
                if (diagonal >= 0 && diagonal < nx)
                {
                    link(lattice.index(layer, row, column), lattice.index(layer, row + 1, diagonal),
                         SpringClass::Planar);
                }
            }
        }
        if (layer == 0)
        {
            continue;
        }
        for (int row = 0; row < nz; ++row)
        {
            const int apexOffset = row % 2 == 0 ? 0 : 1;
            const int lowerOffsets[3][2] = {{0, 0}, {0, 1}, {1, apexOffset}}; // (row, column) below the upper mass
            for (const auto& offset : lowerOffsets)
            {
                for (int column = 0; column < nx; ++column)
                {
                    link(lattice.index(layer, row, column),
                         lattice.index(layer - 1, row + offset[0], column + offset[1]), SpringClass::InterLayer);
                }
            }
        }
    }
}
} // namespace masse
