#pragma once
/// The springs at each mass, as compressed rows (CSR): built once from a sheet's immutable spring ends, so force
/// kernels can gather each mass's springs instead of scattering each spring into two shared masses.
///
/// A mass's springs are listed in increasing spring index: a mass then sums its spring forces in the order a serial
/// scatter over the springs would, whatever the thread count, so the results have the same bits at any thread count.

#include "core/Types.h"

#include <vector>

namespace masse
{
struct SpringEnds;

struct SpringAdjacency
{
    /// One spring seen from one of its masses.
    struct Entry
    {
        Index other;  ///< the mass at the spring's other end
        Index spring; ///< index into the SpringSet
    };
    std::vector<std::size_t> offsets; ///< mass i's springs are entries[offsets[i], offsets[i + 1])
    std::vector<Entry> entries;
    std::size_t springCount = 0;

    std::size_t massCount() const { return offsets.empty() ? 0 : offsets.size() - 1; }
};

/// Builds the adjacency of `massCount` masses joined by `ends` (two linear passes, a counting sort). Throws
/// std::out_of_range for a spring to a mass past the end.
SpringAdjacency buildSpringAdjacency(const std::vector<SpringEnds>& ends, std::size_t massCount);
} // namespace masse
