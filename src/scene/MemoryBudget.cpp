#include "scene/MemoryBudget.h"

#include "core/Format.h"
#include "core/InputError.h"

#include <algorithm>
#include <fstream>
#include <string>
#include <sys/resource.h>
#include <unistd.h>

namespace masse::scene
{
namespace
{
// Bytes per mass: a generous upper estimate, not measured: a TRiMM mass holds about 10
// doubles of state and forces and some four springs of about 8 doubles each, a few hundred bytes with contact and
// Bullet's arrays; 2000 leaves room for the other structures, heat and the reports. Measure with the peak resident
// memory of `masse run` on two large sheets (the difference drops the fixed cost) and replace these.
constexpr double explicitBytesPerMass = 2000.0;
// The implicit integrator's sparse matrix and preconditioner on top (also an unmeasured upper estimate).
constexpr double implicitBytesPerMass = 5000.0;
// Fixed cost: the program, Bullet's world and the room.
constexpr double fixedBytes = 64.0 * 1024 * 1024;
} // namespace

std::size_t massCountOf(const LatticeSpec& spec)
{
    std::size_t masses = 0;
    for (int layer = 0; layer < spec.layers; ++layer)
    {
        masses += std::size_t(std::max(0, spec.countX - layer)) * std::size_t(std::max(0, spec.countZ - layer));
    }
    return masses;
}

double estimatedBytes(const LatticeSpec& spec, IntegratorKind integrator)
{
    // TR-BDF2 keeps a solve (matrix and factor) for each of its two stages and BDF2's for its steps with contact.
    const double solves = isExplicit(integrator) ? 0.0 : integrator == IntegratorKind::TrBdf2 ? 3.0 : 1.0;
    const double perMass = explicitBytesPerMass + solves * (implicitBytesPerMass - explicitBytesPerMass);
    return fixedBytes + perMass * double(massCountOf(spec));
}

double availableBytes()
{
    double available = double(::sysconf(_SC_PHYS_PAGES)) * double(::sysconf(_SC_PAGE_SIZE));
    std::ifstream meminfo("/proc/meminfo");
    std::string key;
    double kilobytes = 0;
    std::string unit;
    while (meminfo >> key >> kilobytes >> unit)
    {
        if (key == "MemAvailable:")
        {
            available = kilobytes * 1024;
            break;
        }
    }
    rlimit limit{};
    if (::getrlimit(RLIMIT_AS, &limit) == 0 && limit.rlim_cur != RLIM_INFINITY)
    {
        available = std::min(available, double(limit.rlim_cur));
    }
    return available;
}

void checkMemory(const LatticeSpec& spec, IntegratorKind integrator)
{
    const double needed = estimatedBytes(spec, integrator);
    const double available = availableBytes();
    if (needed > available)
    {
        constexpr double gib = 1024.0 * 1024 * 1024;
        throw InputError("size", "a " + std::to_string(spec.countX) + "x" + std::to_string(spec.layers) + "x" +
                                     std::to_string(spec.countZ) + " sheet has " + std::to_string(massCountOf(spec)) +
                                     " masses and needs about " + formatNumber("%.3g", needed / gib) +
                                     " GiB of memory, more than the " + formatNumber("%.3g", available / gib) +
                                     " GiB available");
    }
}
} // namespace masse::scene
