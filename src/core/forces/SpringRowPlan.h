#pragma once
/// A sheet's springs and masses grouped by lattice row, so the force kernel can stream through the sheet a band of
/// rows at a time with contiguous loads, vectorised across neighbouring masses.
///
/// Every lattice spring joins masses of one row or of two neighbouring rows (rows run along x; see Lattice.h). A
/// spring belongs to the lower of its two rows, its "spring row". The masses of row r (of every layer) then feel only
/// the springs of spring rows r - 1 and r, so once those two rows' spring forces are known, row r's masses can sum
/// their forces, and a band of rows needs the spring forces of one row before it and nothing else.
///
/// Within a spring row, springs are numbered in runs: spring first + j joins masses a + j and b + j. Within a mass
/// row, masses come in runs whose every mass lists its springs in the same pattern: entry k of mass first + j is the
/// spring in slot (slot_k + j) of its spring row, met at the same end. Each mass's entries keep the adjacency's
/// increasing spring index, so a kernel that sums a mass's entries in order gives the bits of the per-mass gather over
/// SpringAdjacency, at any vector width and thread count. The lattice builders emit each row's springs direction by
/// direction so that the runs are long (a full row); a spring set in another order still gets a valid plan, with
/// shorter runs.

#include "core/Types.h"
#include "core/lattice/SpringAdjacency.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace masse
{
struct SpringEnds;
enum class SpringClass : std::uint8_t;

struct SpringRowPlan
{
    /// Springs [firstSpring, firstSpring + count) joining masses a + j and b + j; their forces go to slots
    /// [firstSlot, firstSlot + count) of their spring row.
    struct SpringRun
    {
        Index firstSpring;
        Index a;
        Index b;
        Index count;
        Index firstSlot;
        Index aLocal = 0; ///< a's place in its band's state copy (see MassRange); unused in the row before a band
        Index bLocal = 0;
        std::uint8_t springClass = 0; ///< the SpringClass of every spring of the run
    };
    /// One spring of a mass run's pattern.
    struct Entry
    {
        Index slot;           ///< slot of the run's first mass; mass first + j reads slot + j
        std::uint8_t sameRow; ///< 1: the spring is in the mass's own spring row r; 0: in row r - 1
        std::uint8_t negated; ///< 1: the mass is the spring's end b, so it feels minus the force on a
    };
    /// Masses [firstMass, firstMass + count) of one row, each with entries [firstEntry, firstEntry + entryCount).
    struct MassRun
    {
        Index firstMass;
        Index count;
        Index firstEntry;
        Index entryCount;
        Index local = 0; ///< firstMass's place in its band's state copy
    };
    /// Masses [firstMass, firstMass + count) of a band, copied to [local, local + count) of the band's state copy.
    struct MassRange
    {
        Index firstMass;
        Index count;
        Index local;
    };

    std::size_t rowCount = 0;
    std::size_t massCount = 0;
    std::size_t springCount = 0;
    /// Spring row r's runs are springRuns[springRunStart[r], springRunStart[r + 1]); it has slotCount[r] slots.
    std::vector<Index> springRunStart;
    std::vector<SpringRun> springRuns;
    std::vector<Index> slotCount;
    /// Mass row r's runs are massRuns[massRunStart[r], massRunStart[r + 1]), in increasing mass index.
    std::vector<Index> massRunStart;
    std::vector<MassRun> massRuns;
    std::vector<Entry> entries;
    /// Rows per band: bands are [k * bandRows, (k + 1) * bandRows), a function of the sheet alone (never of the
    /// thread count), sized so that a band's state and spring forces stay in the core's L2 cache.
    std::size_t bandRows = 1;
    /// Band k's masses (those of its rows, in every layer) are the ranges bandRanges[bandRangeStart[k],
    /// bandRangeStart[k + 1]): one per layer on a lattice. The kernel copies their positions and velocities into a
    /// structure of arrays once per band, so its spring loops load each component contiguously. A band's springs
    /// but those of its last row join only the band's masses; its last row's springs reach into the next band and are
    /// computed before any band starts, from the masses' own arrays.
    std::vector<Index> bandRangeStart;
    std::vector<MassRange> bandRanges;
    std::size_t largestBandMassCount = 0;

    std::size_t largestSlotCount = 0;

    std::size_t bandCount() const { return (rowCount + bandRows - 1) / bandRows; }
};

/// Builds the plan of the masses in rows `massRow` (0-based) joined by springs `ends` of classes `springClass`;
/// nullptr when some spring joins rows more than one apart (no lattice sheet does; such a set keeps the plain
/// per-mass gather).
std::shared_ptr<const SpringRowPlan> buildSpringRowPlan(const std::vector<SpringEnds>& ends,
                                                        const std::vector<SpringClass>& springClass,
                                                        const SpringAdjacency& adjacency,
                                                        const std::vector<int>& massRow);
} // namespace masse
