#include "scene/Pins.h"

#include <algorithm>

namespace masse::scene
{
std::vector<Index> resolvePins(const PinSpec& pins, const Lattice& lattice)
{
    std::vector<Index> result = pins.masses;
    const std::vector<Index> corners = lattice.bottomCorners();
    for (int corner : pins.corners)
    {
        result.push_back(corners[std::size_t(corner)]);
    }
    for (const std::string& edge : pins.edges)
    {
        for (std::size_t i = 0; i < lattice.massCount(); ++i)
        {
            const LatticeCoord c = lattice.coord[i];
            const bool on = (edge == "x_min" && c.column == 0) ||
                            (edge == "x_max" && c.column == lattice.layerCountX(c.layer) - 1) ||
                            (edge == "z_min" && c.row == 0) ||
                            (edge == "z_max" && c.row == lattice.layerCountZ(c.layer) - 1);
            if (on)
            {
                result.push_back(Index(i));
            }
        }
    }
    std::sort(result.begin(), result.end());
    result.erase(std::unique(result.begin(), result.end()), result.end());
    return result;
}
} // namespace masse::scene
