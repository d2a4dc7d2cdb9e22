#pragma once
/// The points of a parameter study: every combination of the values (a full grid), the i-th values together (zip),
/// or a Latin hypercube sample of ranges, reproducible from its seed on any machine.

#include <nlohmann/json.hpp>

#include <cstdint>
#include <vector>

namespace masse::scene
{
/// A value range of a varied key.
struct StudyRange
{
    double min = 0;
    double max = 0;
    bool integer = false; ///< values rounded to whole numbers
};

/// One row per case, one value per parameter; the first parameter varies slowest.
std::vector<std::vector<nlohmann::json>> gridDesign(const std::vector<std::vector<nlohmann::json>>& values);

/// Case i takes the i-th value of every parameter (the lists have one length).
std::vector<std::vector<nlohmann::json>> zipDesign(const std::vector<std::vector<nlohmann::json>>& values);

/// `samples` cases; each range is cut into `samples` equal strata and every stratum of every range holds exactly one
/// case, at a uniformly random place in it. The generator is SplitMix64 with our own uniform mapping, so one seed
/// gives the same cases everywhere (the standard library's distributions differ between implementations).
std::vector<std::vector<nlohmann::json>> latinHypercube(const std::vector<StudyRange>& ranges, std::size_t samples,
                                                        std::uint64_t seed);

/// The values min, min + step, ... up to max (inclusive within a relative 1e-9 of the step).
std::vector<nlohmann::json> stepValues(const StudyRange& range, double step);
/// `count` values evenly from min to max inclusive (count 1: min).
std::vector<nlohmann::json> countValues(const StudyRange& range, std::size_t count);
} // namespace masse::scene
