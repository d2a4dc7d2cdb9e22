#include "SoftBodyTwinSettings.h"
#include "core/Format.h"

#include "core/InputError.h"

#include <cmath>
#include <sstream>

namespace masse::bridge
{
namespace
{
/// Requires lo <= value <= hi, with either end excluded when asked; NaN fails every test.
void requireRange(const char* field, Real value, Real lo, bool loOpen, Real hi, bool hiOpen)
{
    const bool aboveLo = loOpen ? value > lo : value >= lo;
    const bool belowHi = hiOpen ? value < hi : value <= hi;
    if (!(aboveLo && belowHi))
    {
        throw InputError(field, std::string("must be in ") + (loOpen ? "(" : "[") + formatNumber(lo) + ", " +
                                    formatNumber(hi) + (hiOpen ? ")" : "]") + " (got " + formatNumber(value) + ")");
    }
}

void requireCount(const char* field, int value, int lo, int hi)
{
    if (value < lo || value > hi)
    {
        throw InputError(field, "must be a whole number in [" + std::to_string(lo) + ", " + std::to_string(hi) +
                                    "] (got " + std::to_string(value) + ")");
    }
}
} // namespace

void validate(const SoftBodyTwinSettings& settings)
{
    if (settings.kLST)
    {
        requireRange("kLST", *settings.kLST, 0, true, 1, false);
    }
    if (settings.kDP)
    {
        requireRange("kDP", *settings.kDP, 0, false, 1, true);
    }
    if (settings.kDF)
    {
        requireRange("kDF", *settings.kDF, 0, false, 1, false);
    }
    requireRange("kCHR", settings.kCHR, 0, false, 1, false);
    requireRange("kKHR", settings.kKHR, 0, false, 1, false);
    if (settings.margin)
    {
        requireRange("margin", *settings.margin, 0, true, 1, false);
    }
    requireCount("piterations", settings.piterations, 1, 1000);
    requireCount("substeps", settings.substeps, 1, 10000);
    requireRange("sdfCellSize", settings.sdfCellSize, 0.001, false, 1, false);
}
} // namespace masse::bridge
