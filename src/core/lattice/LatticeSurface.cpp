#include "core/lattice/LatticeSurface.h"

#include "core/lattice/SpringTopology.h"

#include <algorithm>

namespace masse
{
std::vector<Triangle> layerTriangles(const Lattice& lattice, int layer)
{
    std::vector<Triangle> triangles;
    const int nx = lattice.layerCountX(layer);
    const int nz = lattice.layerCountZ(layer);
    auto at = [&](int row, int column) { return lattice.index(layer, row, column); };
    for (int row = 0; row + 1 < nz; ++row)
    {
        for (int column = 0; column + 1 < nx; ++column)
        {
            if (lattice.spec.structure != Structure::TRiMM)
            {
                triangles.push_back({at(row, column), at(row, column + 1), at(row + 1, column + 1)});
                triangles.push_back({at(row, column), at(row + 1, column + 1), at(row + 1, column)});
            }
            else if (row % 2 == 0) // the next row is shifted half a spacing to +x
            {
                triangles.push_back({at(row, column), at(row, column + 1), at(row + 1, column)});
                triangles.push_back({at(row, column + 1), at(row + 1, column + 1), at(row + 1, column)});
            }
            else // the next row is shifted to -x
            {
                triangles.push_back({at(row, column), at(row, column + 1), at(row + 1, column + 1)});
                triangles.push_back({at(row, column), at(row + 1, column + 1), at(row + 1, column)});
            }
        }
    }
    // Wind each so its normal points to +y at rest (z grows down the rows, so the order above may point either way).
    for (Triangle& t : triangles)
    {
        const Vec3& a = lattice.position[t[0]];
        const Vec3 normal = (lattice.position[t[1]] - a).cross(lattice.position[t[2]] - a);
        if (normal.y() < 0)
        {
            std::swap(t[1], t[2]);
        }
    }
    return triangles;
}

std::vector<std::vector<Triangle>> rimStrips(const Lattice& lattice)
{
    std::vector<std::vector<Triangle>> strips;
    for (int layer = 0; layer + 1 < lattice.spec.layers; ++layer)
    {
        const int nx = lattice.layerCountX(layer);
        const int nz = lattice.layerCountZ(layer);
        // Per side, the lower layer's border masses and the upper layer's (one fewer), in the same direction.
        const auto border = [&](int which, int line, bool alongRow)
        {
            std::vector<Index> masses;
            const int count = (alongRow ? nx : nz) - which;
            for (int k = 0; k < count; ++k)
            {
                masses.push_back(alongRow ? lattice.index(layer + which, line, k)
                                          : lattice.index(layer + which, k, line));
            }
            return masses;
        };
        const std::array<std::pair<std::vector<Index>, std::vector<Index>>, 4> sides = {{
            {border(0, 0, true), border(1, 0, true)},
            {border(0, nz - 1, true), border(1, nz - 2, true)},
            {border(0, 0, false), border(1, 0, false)},
            {border(0, nx - 1, false), border(1, nx - 2, false)},
        }};
        for (const auto& [lower, upper] : sides)
        {
            std::vector<Triangle>& strip = strips.emplace_back();
            for (std::size_t k = 0; k + 1 < lower.size(); ++k)
            {
                strip.push_back({lower[k], lower[k + 1], upper[k]});
                if (k + 1 < upper.size())
                {
                    strip.push_back({upper[k], lower[k + 1], upper[k + 1]});
                }
            }
        }
    }
    return strips;
}
} // namespace masse

namespace masse
{
namespace
{
/// Cells a side of a surface patch: 128 triangles a patch, so the broadphase's tree has a leaf per 128 triangles.
constexpr int patchCells = 8;

/// Appends the patches of a layer whose triangles start at `first` (layerTriangles' order: two a cell, cell by cell
/// along each row, row after row).
void addPatches(const Lattice& lattice, int layer, Index first, SheetSurface& surface)
{
    const int cellsX = lattice.layerCountX(layer) - 1;
    const int cellsZ = lattice.layerCountZ(layer) - 1;
    for (int rowBlock = 0; rowBlock < cellsZ; rowBlock += patchCells)
    {
        for (int columnBlock = 0; columnBlock < cellsX; columnBlock += patchCells)
        {
            for (int row = rowBlock; row < std::min(rowBlock + patchCells, cellsZ); ++row)
            {
                for (int column = columnBlock; column < std::min(columnBlock + patchCells, cellsX); ++column)
                {
                    const Index cell = first + Index(2 * (row * cellsX + column));
                    surface.patchTriangles.push_back(cell);
                    surface.patchTriangles.push_back(cell + 1);
                }
            }
            surface.patchStart.push_back(surface.patchTriangles.size());
        }
    }
}

/// Most triangles a patch of the rim holds, as many as a patch of a layer holds.
constexpr std::size_t rimPatchTriangles = 2 * patchCells * patchCells;

/// Appends the rim's triangles, each strip in patches of at most rimPatchTriangles (a strip is one side of the
/// sheet: pieces of it are compact, a patch across two sides would not be).
void addRim(const Lattice& lattice, SheetSurface& surface)
{
    for (const std::vector<Triangle>& strip : rimStrips(lattice))
    {
        for (std::size_t k = 0; k < strip.size(); ++k)
        {
            surface.patchTriangles.push_back(Index(surface.triangles.size()));
            surface.triangles.push_back(strip[k]);
            if ((k + 1) % rimPatchTriangles == 0 || k + 1 == strip.size())
            {
                surface.patchStart.push_back(surface.patchTriangles.size());
            }
        }
    }
}

/// The faces inside the sheet: each upper mass with every two of the masses it is joined to in the layer below that
/// are joined to each other (a SaMM or SLaMM mass's pyramid, a TRiMM mass's tetrahedron), so that the springs between
/// the layers are edges; patched by blocks of upper masses.
void addInnerFaces(const Lattice& lattice, SheetSurface& surface)
{
    std::vector<Edge> planar;
    std::vector<std::vector<Index>> below(lattice.massCount());
    for (const SpringEnds& spring : lattice.springs.ends())
    {
        const LatticeCoord& a = lattice.coord[spring.a];
        const LatticeCoord& b = lattice.coord[spring.b];
        if (a.layer == b.layer)
        {
            planar.push_back({std::min(spring.a, spring.b), std::max(spring.a, spring.b)});
        }
        else if (b.layer == a.layer + 1)
        {
            below[spring.b].push_back(spring.a);
        }
        else if (a.layer == b.layer + 1)
        {
            below[spring.a].push_back(spring.b);
        }
    }
    std::sort(planar.begin(), planar.end());
    for (int layer = 1; layer < lattice.spec.layers; ++layer)
    {
        const int nx = lattice.layerCountX(layer);
        const int nz = lattice.layerCountZ(layer);
        for (int rowBlock = 0; rowBlock < nz; rowBlock += patchCells)
        {
            for (int columnBlock = 0; columnBlock < nx; columnBlock += patchCells)
            {
                for (int row = rowBlock; row < std::min(rowBlock + patchCells, nz); ++row)
                {
                    for (int column = columnBlock; column < std::min(columnBlock + patchCells, nx); ++column)
                    {
                        const Index u = lattice.index(layer, row, column);
                        std::vector<Index>& lower = below[u];
                        std::sort(lower.begin(), lower.end());
                        for (std::size_t i = 0; i < lower.size(); ++i)
                        {
                            for (std::size_t j = i + 1; j < lower.size(); ++j)
                            {
                                if (std::binary_search(planar.begin(), planar.end(), Edge{lower[i], lower[j]}))
                                {
                                    surface.patchTriangles.push_back(Index(surface.triangles.size()));
                                    surface.triangles.push_back({u, lower[i], lower[j]});
                                }
                            }
                        }
                    }
                }
                surface.patchStart.push_back(surface.patchTriangles.size());
            }
        }
    }
}
} // namespace

SheetSurface sheetSurface(const Lattice& lattice, SheetFaces faces)
{
    SheetSurface surface;
    surface.triangles = layerTriangles(lattice, 0);
    surface.patchStart.push_back(0);
    addPatches(lattice, 0, 0, surface);
    const int top = lattice.spec.layers - 1;
    if (top > 0)
    {
        const std::vector<Triangle> upper = layerTriangles(lattice, top);
        addPatches(lattice, top, Index(surface.triangles.size()), surface);
        surface.triangles.insert(surface.triangles.end(), upper.begin(), upper.end());
    }
    if (faces == SheetFaces::Volume)
    {
        addRim(lattice, surface);
        addInnerFaces(lattice, surface);
    }
    for (const Triangle& t : surface.triangles)
    {
        surface.vertices.insert(surface.vertices.end(), t.begin(), t.end());
        for (int k = 0; k < 3; ++k)
        {
            const Index a = t[std::size_t(k)];
            const Index b = t[std::size_t((k + 1) % 3)];
            surface.edges.push_back({std::min(a, b), std::max(a, b)});
        }
    }
    std::sort(surface.vertices.begin(), surface.vertices.end());
    surface.vertices.erase(std::unique(surface.vertices.begin(), surface.vertices.end()), surface.vertices.end());
    std::sort(surface.edges.begin(), surface.edges.end());
    surface.edges.erase(std::unique(surface.edges.begin(), surface.edges.end()), surface.edges.end());
    surface.triangleEdges.reserve(surface.triangles.size());
    for (const Triangle& t : surface.triangles)
    {
        std::array<Index, 3> edges{};
        for (int k = 0; k < 3; ++k)
        {
            const Index a = t[std::size_t(k)];
            const Index b = t[std::size_t((k + 1) % 3)];
            const Edge edge{std::min(a, b), std::max(a, b)};
            edges[std::size_t(k)] =
                Index(std::lower_bound(surface.edges.begin(), surface.edges.end(), edge) - surface.edges.begin());
        }
        surface.triangleEdges.push_back(edges);
    }
    return surface;
}
} // namespace masse
