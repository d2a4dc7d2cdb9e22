#pragma once
/// The surface of a lattice layer as triangles, for drawing, frame files and per-mass areas; the sheet's rim; and the
/// sheet's faces (its bottom and top layers' triangles, for the edge contact also its rim and the faces inside it, with
/// their edges) for the contacts that see the sheet as a surface.

#include "core/lattice/Lattice.h"

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

/// The sheet's rim: per pair of neighbouring layers and per side (rows 0 and last, columns 0 and last), the strip of
/// triangles that joins the lower layer's border to the upper one's. Each upper mass sits over the gap between two
/// lower ones, so the strip zips the two rows: (b_k, b_k+1, t_k) and (t_k, b_k+1, t_k+1); neighbouring sides share
/// their corner masses, so the strips meet without a gap. Not wound any particular way.
std::vector<std::vector<Triangle>> rimStrips(const Lattice& lattice);

/// The sheet's surface: the triangles of its bottom layer, then those of its top layer (one layer's if the sheet has
/// one), then, if asked for, its rim's and the faces inside it (SheetFaces); each edge of them once and each mass of
/// them once.
struct SheetSurface
{
    std::vector<Triangle> triangles;
    std::vector<Edge> edges;                         ///< sorted
    std::vector<std::array<Index, 3>> triangleEdges; ///< per triangle, its three edges (into edges)
    std::vector<Index> vertices;                     ///< the surface's masses, increasing
    /// The triangles in patches (blocks of up to 8 x 8 cells of one layer; pieces of one side's rim; blocks of 8 x 8
    /// upper masses' inner faces): each a compact piece of the sheet however it folds, the leaves of a broadphase over
    /// the surface. Patch p holds patchTriangles[patchStart[p],
    /// patchStart[p + 1]).
    std::vector<std::size_t> patchStart;
    std::vector<Index> patchTriangles;
};

/// Which faces of the sheet sheetSurface lists.
enum class SheetFaces
{
    /// The bottom and top layers' triangles: the sheet as the self-contact and the drawing see it.
    Layers,
    /// Those, then the rim's (rimStrips), then the faces inside the sheet: each mass above the bottom layer with every
    /// two of the masses it is joined to in the layer below that are joined to each other (a SaMM or SLaMM mass's
    /// pyramid, a TRiMM mass's tetrahedron). Every spring between two layers is then one of the edges, so nothing
    /// the edge contact keeps out of an obstacle leaves a spring across it.
    Volume,
};

/// With SheetFaces::Volume the rim comes in patches of one side of one layer gap (pieces of at most 128 triangles),
/// the inner faces in patches of 8 x 8 upper masses.
SheetSurface sheetSurface(const Lattice& lattice, SheetFaces faces = SheetFaces::Layers);
} // namespace masse
