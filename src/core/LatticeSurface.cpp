#include "LatticeSurface.h"

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
