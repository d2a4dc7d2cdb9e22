#pragma once
/// The springs at each mass, grouped into runs that a vectorised kernel walks with contiguous loads only.
///
/// On a lattice, consecutive masses of a row have the same neighbours shifted by one: mass i's spring to i + o is
/// followed by mass i + 1's spring to i + 1 + o, and the lattice numbers those springs consecutively too
/// (springOrderForRuns). The force kernel walks such runs with contiguous loads only, so its loops vectorise without
/// gathers or scatters, in two passes:
/// - spring runs: springs [firstSpring, firstSpring + count), spring firstSpring + t joining masses firstMass + t and
///   firstMass + t + otherOffset; the kernel computes each spring's force once, as a scale of its direction;
/// - mass runs: masses [firstMass, firstMass + count), mass firstMass + t using spring firstSpring + t to mass
///   firstMass + t + otherOffset; the kernel adds each mass's springs into that mass only, so no two threads write one
///   mass.
///
/// Each mass orders its springs by the offset (other - mass), and its k-th spring in that order belongs to a mass run
/// of rank k. The kernel adds rank 0's runs, then rank 1's, ...: every mass sums its spring forces in increasing
/// offset, whatever range or thread computes it. Any topology is valid; regular lattices give runs as long as a row,
/// an irregular spring set gives short runs (correct, only slower).

#include "Types.h"

#include <cstdint>
#include <vector>

namespace masse
{
struct SpringEnds;

struct SpringRun
{
    Index firstMass;
    Index count;
    Index firstSpring;
    std::int64_t otherOffset; ///< the other end of mass i's spring is mass i + otherOffset
};

struct SpringRuns
{
    /// Mass runs of rank r are runs[rankStart[r], rankStart[r + 1]), sorted by firstMass and disjoint.
    std::vector<SpringRun> runs;
    /// Spring runs, sorted by firstSpring, covering every spring once.
    std::vector<SpringRun> springRuns;
    std::vector<std::size_t> rankStart;
    std::size_t springCount = 0;
    std::size_t massCount = 0;

    std::size_t rankCount() const { return rankStart.empty() ? 0 : rankStart.size() - 1; }
};

/// Builds the runs of `massCount` masses joined by `ends`.
SpringRuns buildSpringRuns(const std::vector<SpringEnds>& ends, std::size_t massCount);

/// The order in which springs make the longest runs: by signed offset (b - a), then by a. Springs of one lattice
/// direction and row then have consecutive indices. Returns the permutation: position k holds the old index of the
/// spring that goes k-th.
std::vector<std::size_t> springOrderForRuns(const std::vector<SpringEnds>& ends);
} // namespace masse
