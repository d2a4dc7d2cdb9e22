#include "LatticeSurface.h"

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
} // namespace

SheetSurface sheetSurface(const Lattice& lattice)
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
