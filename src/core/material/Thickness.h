#pragma once
/// Local sheet thickness from the change of area each mass stands for: h = h0 A0 / A (the material is
/// incompressible, so a patch that grows thinner keeps its volume; physics.md section 4).
///
/// Each layer is cut into cells: the triangles of a TRiMM layer, the squares of a square lattice's layer. A mass
/// stands for a third of the area of each triangle it is a corner of, or a quarter of each square (a bent square's area
/// is the mean of its two splits into triangles, along either diagonal, so that it does not depend on the square's
/// orientation and a mirror-symmetric sheet has a mirror-symmetric thickness field). These shares
/// partition the layer's surface, so the volume sum h_i A_i = h0 A0 holds exactly at any deformation (integrating
/// the thickness linearly over the cells gives the same sum). How well h follows the continuum h0 / J, with J the
/// local area stretch of the deformation, is the discretisation's accuracy: second order in the lattice spacing
/// away from the sheet's edges.
///
/// Each mass gets the thickness of its own layer's cells: every layer measures the stretch of its own surface, and
/// where the sheet bends the outer layer stretches more than the inner one. The sheet's thinnest wall is the smallest
/// of these over every mass of every layer, the one value that summary.json, masses.csv, the frames and the map's title
/// report. The volume is summed over the bottom layer, the sheet's underside as it meets a mould. A mass that belongs
/// to no cell (the lone mass of a tapered top layer) is given one cell's area, spacingX * spacingZ, for good, and keeps
/// h0.

#include "core/lattice/Lattice.h"

#include <vector>

namespace masse
{
class SheetThickness
{
public:
    /// `thickness` is the sheet's initial thickness h0 (m, > 0); the lattice's rest positions are the initial shape.
    SheetThickness(const Lattice& lattice, Real thickness);

    /// Recomputes areas, normals and thicknesses for the positions x (one per mass of the lattice); nothing when x
    /// holds the same bits as at the last update (a frame's springs and its heat step read the sheet at the same
    /// positions, one at the frame's end and one at the next frame's start).
    void update(const std::vector<Vec3>& x);

    Real initialThickness() const { return m_initialThickness; }
    /// m, per mass, from the last update (h0 before the first).
    const std::vector<Real>& thickness() const { return m_thickness; }
    /// m^2, the area each mass stands for in its layer, from the last update.
    const std::vector<Real>& area() const { return m_area; }
    const std::vector<Real>& restArea() const { return m_restArea; }
    /// Unit normal of the layer at each mass, area-weighted over its cells, pointing to the sheet's top side (+y at
    /// rest).
    const std::vector<Vec3>& normal() const { return m_normal; }
    /// Layer of each mass (0 is the bottom).
    const std::vector<int>& layer() const { return m_layer; }
    int layerCount() const { return m_layerCount; }

    /// The cells: cornersPerCell() consecutive mass indices each, counter-clockwise seen from the top side.
    const std::vector<Index>& cells() const { return m_cells; }
    int cornersPerCell() const { return m_cornersPerCell; }

    /// The thinnest wall, over every mass of every layer, from the last update.
    Real minimumThickness() const { return m_minimumThickness; }
    /// The mass (of any layer) where the sheet is thinnest.
    Index thinnestMass() const { return m_thinnestMass; }
    /// sum h_i A_i over the bottom layer (m^3); equals restVolume() by construction.
    Real volume() const { return m_volume; }
    /// h0 A0 (m^3).
    Real restVolume() const { return m_restVolume; }

private:
    /// Accumulates per-mass areas and normals (vector areas) of the cells for positions x, the layers on the pool.
    void accumulate(const std::vector<Vec3>& x, std::vector<Real>& area, std::vector<Vec3>& vectorArea) const;

    Real m_initialThickness;
    int m_cornersPerCell = 3;
    int m_layerCount = 1;
    std::vector<Index> m_cells;
    std::vector<std::size_t> m_layerCellStart; ///< per layer and one past, its first cell (cells() in cells)
    std::vector<int> m_layer;
    std::vector<std::uint8_t> m_cellless; ///< masses of no cell
    std::vector<Real> m_restArea;
    std::vector<Real> m_area;
    std::vector<Vec3> m_vectorArea;
    std::vector<Vec3> m_updatedAt; ///< the positions of the last update
    std::vector<Vec3> m_normal;
    std::vector<Real> m_thickness;
    Real m_minimumThickness = 0;
    Index m_thinnestMass = 0;
    Real m_volume = 0;
    Real m_restVolume = 0;
};
} // namespace masse
