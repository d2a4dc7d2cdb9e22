#pragma once
/// The nearest of a list of names to one that was mistyped, for the "did you mean" of every message about a name the
/// user chose: scene keys, list names, --set paths, subcommands.

#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

namespace masse
{
/// Edit distance (insertions, deletions, substitutions) between two strings.
inline std::size_t editDistance(const std::string& a, const std::string& b)
{
    std::vector<std::size_t> previous(b.size() + 1);
    std::vector<std::size_t> current(b.size() + 1);
    for (std::size_t j = 0; j <= b.size(); ++j)
    {
        previous[j] = j;
    }
    for (std::size_t i = 1; i <= a.size(); ++i)
    {
        current[0] = i;
        for (std::size_t j = 1; j <= b.size(); ++j)
        {
            const std::size_t substitution = previous[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
            current[j] = std::min({previous[j] + 1, current[j - 1] + 1, substitution});
        }
        std::swap(previous, current);
    }
    return previous[b.size()];
}

/// The name of `names` nearest to `name`, or "" when none is near enough to be the one meant (within 2 edits, or a
/// third of the name's length for long names). The first of equally near names wins.
inline std::string nearestName(const std::string& name, const std::vector<std::string>& names)
{
    std::string best;
    std::size_t bestDistance = 0;
    for (const std::string& candidate : names)
    {
        const std::size_t d = editDistance(name, candidate);
        if (best.empty() || d < bestDistance)
        {
            best = candidate;
            bestDistance = d;
        }
    }
    return !best.empty() && bestDistance <= std::max<std::size_t>(2, best.size() / 3) ? best : "";
}

/// " (did you mean 'NAME'?)" for the nearest name, or "".
inline std::string didYouMean(const std::string& name, const std::vector<std::string>& names)
{
    const std::string nearest = nearestName(name, names);
    return nearest.empty() ? "" : " (did you mean '" + nearest + "'?)";
}
} // namespace masse
