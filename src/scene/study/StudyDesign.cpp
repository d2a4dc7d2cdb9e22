#include "scene/study/StudyDesign.h"

#include <cmath>
#include <numeric>

namespace masse::scene
{
namespace
{
/// SplitMix64 (Steele, Lea and Flood 2014): tiny, fully specified, good enough to place samples in strata.
class SplitMix64
{
public:
    explicit SplitMix64(std::uint64_t seed) : m_state(seed) {}
    std::uint64_t next()
    {
        std::uint64_t z = (m_state += 0x9e3779b97f4a7c15ULL);
        z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
        z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
        return z ^ (z >> 31);
    }
    /// Uniform in [0, 1) from the top 53 bits.
    double uniform() { return double(next() >> 11) * 0x1.0p-53; }
    /// Uniform in [0, n) without modulo bias (rejection).
    std::uint64_t below(std::uint64_t n)
    {
        const std::uint64_t limit = UINT64_MAX - UINT64_MAX % n;
        std::uint64_t x = next();
        while (x >= limit)
        {
            x = next();
        }
        return x % n;
    }

private:
    std::uint64_t m_state;
};

nlohmann::json valueOf(const StudyRange& range, double x)
{
    if (range.integer)
    {
        return std::int64_t(std::llround(x));
    }
    return x;
}
} // namespace

std::vector<std::vector<nlohmann::json>> gridDesign(const std::vector<std::vector<nlohmann::json>>& values)
{
    std::vector<std::vector<nlohmann::json>> cases(1);
    for (const std::vector<nlohmann::json>& parameter : values)
    {
        std::vector<std::vector<nlohmann::json>> grown;
        for (const std::vector<nlohmann::json>& partial : cases)
        {
            for (const nlohmann::json& value : parameter)
            {
                grown.push_back(partial);
                grown.back().push_back(value);
            }
        }
        cases = std::move(grown);
    }
    return values.empty() ? std::vector<std::vector<nlohmann::json>>{} : cases;
}

std::vector<std::vector<nlohmann::json>> zipDesign(const std::vector<std::vector<nlohmann::json>>& values)
{
    std::vector<std::vector<nlohmann::json>> cases;
    const std::size_t count = values.empty() ? 0 : values.front().size();
    for (std::size_t i = 0; i < count; ++i)
    {
        cases.emplace_back();
        for (const std::vector<nlohmann::json>& parameter : values)
        {
            cases.back().push_back(parameter.at(i));
        }
    }
    return cases;
}

std::vector<std::vector<nlohmann::json>> latinHypercube(const std::vector<StudyRange>& ranges, std::size_t samples,
                                                        std::uint64_t seed)
{
    SplitMix64 random(seed);
    std::vector<std::vector<nlohmann::json>> cases(samples);
    for (const StudyRange& range : ranges)
    {
        std::vector<std::size_t> stratum(samples);
        std::iota(stratum.begin(), stratum.end(), std::size_t(0));
        for (std::size_t i = samples; i > 1; --i) // Fisher-Yates
        {
            std::swap(stratum[i - 1], stratum[random.below(i)]);
        }
        for (std::size_t i = 0; i < samples; ++i)
        {
            const double u = (double(stratum[i]) + random.uniform()) / double(samples);
            cases[i].push_back(valueOf(range, range.min + u * (range.max - range.min)));
        }
    }
    return cases;
}

std::vector<nlohmann::json> stepValues(const StudyRange& range, double step)
{
    std::vector<nlohmann::json> values;
    for (std::size_t i = 0;; ++i)
    {
        const double x = range.min + double(i) * step;
        if (x > range.max + 1e-9 * step || i > 1000000)
        {
            break;
        }
        values.push_back(valueOf(range, x));
    }
    return values;
}

std::vector<nlohmann::json> countValues(const StudyRange& range, std::size_t count)
{
    std::vector<nlohmann::json> values;
    for (std::size_t i = 0; i < count; ++i)
    {
        const double x = count == 1 ? range.min : range.min + (range.max - range.min) * double(i) / double(count - 1);
        values.push_back(valueOf(range, x));
    }
    return values;
}
} // namespace masse::scene
