#include "core/lattice/Lattice.h"

#include "core/InputError.h"
#include "core/NamedEnum.h"

#include <algorithm>
#include <cctype>
#include <charconv>

namespace masse
{
namespace
{
// The largest count per side: 4096 x 4096 x 2 is about 33 million masses, far past interactive use, and keeps every
// index inside 32 bits.
constexpr int maxCount = 4096;
constexpr int maxLayers = 64;
} // namespace

Structure parseStructure(std::string_view name)
{
    return parseEnum(structureTable, name, "structure", "structure");
}

std::string_view structureName(Structure structure)
{
    return enumName(structureTable, structure);
}

std::string structureNameList()
{
    return nameList(structureTable);
}

void parseSize(std::string_view text, LatticeSpec& spec)
{
    int values[3] = {0, 0, 0};
    std::size_t pos = 0;
    for (int part = 0; part < 3; ++part)
    {
        if (part > 0)
        {
            if (pos >= text.size() || (text[pos] != 'x' && text[pos] != 'X'))
            {
                throw InputError("size", "expected NxLxN, e.g. 8x2x8 (got '" + std::string(text) + "')");
            }
            ++pos;
        }
        const char* first = text.data() + pos;
        const char* last = text.data() + text.size();
        auto [end, error] = std::from_chars(first, last, values[part]);
        if (error != std::errc() || end == first)
        {
            throw InputError("size", "expected NxLxN, e.g. 8x2x8 (got '" + std::string(text) + "')");
        }
        pos = std::size_t(end - text.data());
    }
    if (pos != text.size())
    {
        throw InputError("size", "expected NxLxN, e.g. 8x2x8 (got '" + std::string(text) + "')");
    }
    spec.countX = values[0];
    spec.layers = values[1];
    spec.countZ = values[2];
}

void validate(const LatticeSpec& spec)
{
    const std::string sizeText =
        std::to_string(spec.countX) + "x" + std::to_string(spec.layers) + "x" + std::to_string(spec.countZ);
    if (spec.structure == Structure::Square2D)
    {
        if (spec.layers != 1)
        {
            throw InputError("size", "square2d has exactly 1 layer (got " + sizeText + ", use Nx1xN)");
        }
    }
    else if (spec.layers < 2 || spec.layers > maxLayers)
    {
        throw InputError("size", std::string(structureName(spec.structure)) + " needs 2 to " +
                                     std::to_string(maxLayers) + " layers (got " + sizeText + ")");
    }
    // Layer l has N - l masses per side: the top layer (l = L - 1) needs at least one, the bottom at least two.
    const int minCount = std::max(2, spec.layers);
    if (spec.countX < minCount || spec.countZ < minCount)
    {
        throw InputError("size", "expected NxLxN with N >= " + std::to_string(minCount) + " for " +
                                     std::to_string(spec.layers) + " layer(s) (got " + sizeText + ")");
    }
    if (spec.countX > maxCount || spec.countZ > maxCount)
    {
        throw InputError("size", "N must be <= " + std::to_string(maxCount) + " (got " + sizeText + ")");
    }
    for (int axis = 0; axis < 3; ++axis)
    {
        if (!std::isfinite(spec.minCorner[axis]) || !std::isfinite(spec.maxCorner[axis]))
        {
            throw InputError(std::isfinite(spec.minCorner[axis]) ? "maxCorner" : "minCorner", "must be finite numbers");
        }
    }
    if (!(spec.maxCorner.x() > spec.minCorner.x()) || !(spec.maxCorner.z() > spec.minCorner.z()))
    {
        throw InputError("maxCorner", "must exceed the min corner along x and z");
    }
    if (spec.layers > 1 && !(spec.maxCorner.y() > spec.minCorner.y()))
    {
        throw InputError("maxCorner", "must exceed the min corner along y for a multi-layer sheet (the layers are "
                                      "stacked along y)");
    }
}

std::vector<Index> Lattice::bottomCorners() const
{
    const int lastRow = spec.countZ - 1;
    const int lastColumn = spec.countX - 1;
    return {index(0, 0, 0), index(0, 0, lastColumn), index(0, lastRow, 0), index(0, lastRow, lastColumn)};
}

Lattice buildLattice(const LatticeSpec& spec)
{
    validate(spec);
    Lattice lattice;
    lattice.spec = spec;
    if (spec.structure == Structure::TRiMM)
    {
        buildTriangularLattice(lattice);
    }
    else
    {
        buildSquareLattice(lattice);
    }
    std::vector<int> row(lattice.massCount());
    for (std::size_t i = 0; i < row.size(); ++i)
    {
        row[i] = lattice.coord[i].row;
    }
    lattice.springs.setRowPlan(buildSpringRowPlan(lattice.springs.ends(), lattice.springs.classes(),
                                                  lattice.springs.adjacency(lattice.massCount()), row));
    return lattice;
}
} // namespace masse
