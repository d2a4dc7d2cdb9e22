#pragma once
/// The surface of a lattice layer as triangles, for drawing, frame files and per-mass areas.

#include "Lattice.h"

#include <array>
#include <vector>

namespace masse
{
using Triangle = std::array<Index, 3>;

/// The triangles of one layer, wound counter-clockwise seen from +y in the lattice's rest configuration (so their
/// normals point up). TRiMM layers are triangulated by their own springs; a square cell is split along its
/// (row, column) to (row + 1, column + 1) diagonal, where SLaMM has its brace.
std::vector<Triangle> layerTriangles(const Lattice& lattice, int layer);
} // namespace masse
