#pragma once
/// Sheet lattices of the paper's section 5: the 2D square grid, SaMM, SLaMM and TRiMM.
///
/// A sheet of size NX x L x NZ lies in the x-z plane with its L layers stacked along +y (y is up, as in the paper's
/// room). Layer l holds (NX - l) x (NZ - l) masses: each higher layer sits over the cells of the layer below, as the
/// paper describes, so the sheet tapers by one mass per side and layer. Masses are numbered layer by layer, row (z) by
/// row, column (x) fastest. Layouts and pictures: SquareLattice.cpp and TriangularLattice.cpp.

#include "core/NamedEnum.h"
#include "core/Types.h"
#include "core/lattice/SpringSet.h"

#include <algorithm>
#include <string>
#include <string_view>
#include <vector>

namespace masse
{
enum class Structure
{
    Square2D, ///< one layer, springs along grid lines only (paper figure 4)
    SaMM,     ///< square layers; each upper mass joined to the four masses of the square below (figure 5)
    SLaMM,    ///< SaMM plus one diagonal brace in every square of every layer (figure 6)
    TRiMM,    ///< triangular layers; each upper mass joined to the three masses of the triangle below (figure 7)
};

/// The registry of structures, one entry each in the order menus and help list them: the scene reader's choice, the
/// viewer's menu and the commands' help read it, and data/scenes/README.md's `sheet` table names each (SceneReference).
inline constexpr EnumName<Structure> structureTable[] = {
    {Structure::Square2D, "square2d"},
    {Structure::SaMM, "samm"},
    {Structure::SLaMM, "slamm"},
    {Structure::TRiMM, "trimm"},
};

/// Parses a registered name (any case); throws InputError naming the allowed names.
Structure parseStructure(std::string_view name);
std::string_view structureName(Structure structure);
/// "square2d, samm, slamm or trimm", from the registry, for help strings.
std::string structureNameList();

/// Paper Table 1 defaults, in SI units.
struct LatticeSpec
{
    Structure structure = Structure::TRiMM;
    int countX = 8;                         ///< masses along x in the bottom layer (N)
    int layers = 2;                         ///< L
    int countZ = 8;                         ///< masses along z in the bottom layer (N)
    Vec3 minCorner = Vec3(-0.2, 0.3, -0.2); ///< m, Table 1 sheet box
    Vec3 maxCorner = Vec3(0.8, 0.4, 0.8);   ///< m
};

/// Parses "NxLxN" (e.g. "8x2x8") into the counts of a spec; throws InputError on a malformed size.
void parseSize(std::string_view text, LatticeSpec& spec);

/// Throws InputError if the spec cannot make a lattice; the message names the value and the allowed range.
void validate(const LatticeSpec& spec);

/// Where a mass sits in the lattice.
struct LatticeCoord
{
    int layer;
    int row;    ///< along z
    int column; ///< along x
};

/// Built lattice: rest positions, spring topology, and each mass's place in the lattice.
struct Lattice
{
    LatticeSpec spec;
    std::vector<Vec3> position;
    std::vector<LatticeCoord> coord;
    SpringSet springs; ///< topology only; coefficients are set when a sheet is made from the lattice
    /// First mass index of each layer, plus one past the end.
    std::vector<Index> layerStart;
    Real spacingX = 0; ///< m, distance between neighbouring columns
    Real spacingZ = 0; ///< m, distance between neighbouring rows
    /// m, the smaller of the two spacings (0 for a lattice one mass wide along a side).
    Real smallerSpacing() const { return std::min(spacingX, spacingZ); }

    std::size_t massCount() const { return position.size(); }
    std::size_t springCount() const { return springs.size(); }
    int layerCountX(int layer) const { return spec.countX - layer; }
    int layerCountZ(int layer) const { return spec.countZ - layer; }
    Index index(int layer, int row, int column) const
    {
        return layerStart[std::size_t(layer)] + Index(row * layerCountX(layer) + column);
    }
    /// The four corner masses of the bottom layer: (row 0, col 0), (0, last), (last, 0), (last, last).
    std::vector<Index> bottomCorners() const;
};

/// Builds the lattice for a valid spec (calls validate first).
Lattice buildLattice(const LatticeSpec& spec);

// Builders of each family, called by buildLattice with a validated spec.
void buildSquareLattice(Lattice& lattice);
void buildTriangularLattice(Lattice& lattice);
} // namespace masse
