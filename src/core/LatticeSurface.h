#pragma once
/// The surface of a lattice layer as triangles, for drawing, frame files and per-mass areas, and the sheet's outer
/// surface (its bottom and top layers' triangles and their edges) for the contacts that see the sheet as a surface.

#include "Lattice.h"

#include <array>
#include <vector>

namespace masse
{
using Triangle = std::array<Index, 3>;
/// Two masses, the lower index first.
using Edge = std::array<Index, 2>;

/// The triangles of one layer, wound counter-clockwise seen from +y in the lattice's rest configuration (so their
/// normals point up). TRiMM layers are triangulated by their own springs; a square cell is split along its
/// (row, column) to (row + 1, column + 1) diagonal, where SLaMM has its brace.
std::vector<Triangle> layerTriangles(const Lattice& lattice, int layer);

/// The sheet's outer surface: the triangles of its bottom layer, then those of its top layer (one layer's if the
/// sheet has one), each edge of them once and each mass of them once.
struct SheetSurface
{
    std::vector<Triangle> triangles;
    std::vector<Edge> edges;                         ///< sorted
    std::vector<std::array<Index, 3>> triangleEdges; ///< per triangle, its three edges (into edges)
    std::vector<Index> vertices;                     ///< the surface's masses, increasing
    /// The triangles in patches, blocks of up to 8 x 8 cells of one layer: each a compact piece of the sheet however
    /// it folds, the leaves of a broadphase over the surface. Patch p holds patchTriangles[patchStart[p],
    /// patchStart[p + 1]).
    std::vector<std::size_t> patchStart;
    std::vector<Index> patchTriangles;
};

SheetSurface sheetSurface(const Lattice& lattice);
} // namespace masse
