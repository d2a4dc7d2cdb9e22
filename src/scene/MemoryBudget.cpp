#include "scene/MemoryBudget.h"

#include "core/Format.h"
#include "core/InputError.h"
#include "scene/reports/WebbingReport.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <string>
#include <sys/resource.h>
#include <unistd.h>

namespace masse::scene
{
namespace
{
// The model's constants, from the peak resident memory (GNU time's %M) of `masse run data/scenes/sag.json --threads 1
// --duration 0.006 --set integrator.dt=0.002` at 64x2x64, 128x2x128 and 256x2x256 (8,065 to 130,561 masses) with
// each integrator and preconditioner, and of thick lattices up to 24x24x24; each term is the difference between two
// runs that differ in it, rounded up by a quarter or more.
//
// The program, its libraries, Bullet's world and the room (11 MB measured).
constexpr double fixedBytes = 48.0 * 1024 * 1024;
// Per mass: positions, velocities, forces, springs, heat, contact lists and reports of an explicit run (2.2 KB).
constexpr double explicitBytesPerMass = 2600.0;
// The implicit solve's matrix, its copies and the conjugate gradient's vectors, per mass and per solve kept (1.9 KB).
constexpr double implicitBytesPerMass = 2600.0;
// The preconditioner on top, per mass: multigrid's levels (3.0 KB); Cholesky's factor grows faster than the sheet
// (its fill under a nested dissection order is about n log n for a two-layer sheet), 1.05 KB times log2 of the masses
// at every size measured. A thick lattice fills far more (the factor of a block grows as n^(4/3)): its term is
// multiplied by (layers / 2)^(2/3), which covers 16x16x16 and 24x24x24 by about twice.
constexpr double multigridBytesPerMass = 3600.0;
constexpr double choleskyBytesPerMassAndLog = 1300.0;
// The sheet's surface against itself (self-collision and the webbing report): the triangles, their tree and lists
// (1.4 KB per mass), and per mass the triangles within twice the contact radius at rest, which grow as
// q = (2 radius / spacing)^2: 84 to 100 bytes per mass and unit of q.
constexpr double surfaceBytesPerMass = 1700.0;
constexpr double surfaceBytesPerMassAndRatio = 120.0;
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

namespace
{
/// estimatedBytes with the implicit solve's preconditioner given apart from the spec's, so that checkMemory can weigh
/// another one without copying the spec.
double estimatedBytesWith(const SceneSpec& spec, PreconditionerKind preconditionerKind)
{
    const LatticeSpec& lattice = spec.sheet.lattice;
    const double masses = double(massCountOf(lattice));
    double perMass = explicitBytesPerMass;
    const IntegratorKind integrator = spec.time.integrator;
    if (!isExplicit(integrator))
    {
        const double solves = double(solvesKept(integrator));
        double preconditioner = 0;
        switch (preconditionerKind)
        {
        case PreconditionerKind::Jacobi:
            break;
        case PreconditionerKind::Multigrid:
            preconditioner = multigridBytesPerMass;
            break;
        case PreconditionerKind::Cholesky:
            preconditioner = choleskyBytesPerMassAndLog * std::log2(std::max(masses, 2.0)) *
                             std::pow(std::max(1.0, double(lattice.layers) / 2), 2.0 / 3.0);
            break;
        }
        perMass += solves * (implicitBytesPerMass + preconditioner);
    }
    double bytes = fixedBytes + perMass * masses;
    if (spec.selfCollision || reportsWebbing(spec))
    {
        const auto spacingAlong = [](Real extent, int count) { return count > 1 ? extent / Real(count - 1) : extent; };
        const Vec3 extent = lattice.maxCorner - lattice.minCorner;
        const double spacing = std::max(
            std::min(spacingAlong(extent.x(), lattice.countX), spacingAlong(extent.z(), lattice.countZ)), 1e-12);
        const double ratio = std::pow(2 * spec.contact.radius / spacing, 2);
        bytes += masses * (surfaceBytesPerMass + surfaceBytesPerMassAndRatio * ratio);
    }
    return bytes;
}
} // namespace

double estimatedBytes(const SceneSpec& spec)
{
    return estimatedBytesWith(spec, spec.time.implicit.preconditioner);
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

void checkMemory(const SceneSpec& spec)
{
    const LatticeSpec& lattice = spec.sheet.lattice;
    const double needed = estimatedBytes(spec);
    const double available = availableBytes();
    if (needed <= available)
    {
        return;
    }
    constexpr double gib = 1024.0 * 1024 * 1024;
    const auto gibibytes = [&](double bytes) { return formatNumber("%.3g", bytes / gib) + " GiB"; };
    std::string message = "a " + std::to_string(lattice.countX) + "x" + std::to_string(lattice.layers) + "x" +
                          std::to_string(lattice.countZ) + " sheet has " + std::to_string(massCountOf(lattice)) +
                          " masses and needs about " + gibibytes(needed) + " of memory with the " +
                          std::string(integratorName(spec.time.integrator)) + " integrator";
    if (!isExplicit(spec.time.integrator))
    {
        message += " and the " + std::string(preconditionerName(spec.time.implicit.preconditioner)) + " preconditioner";
    }
    message += ", more than the " + gibibytes(available) + " available";
    // The factor is most of an implicit run's memory: say so when the multigrid preconditioner would fit.
    if (!isExplicit(spec.time.integrator) && spec.time.implicit.preconditioner == PreconditionerKind::Cholesky)
    {
        const double lighter = estimatedBytesWith(spec, PreconditionerKind::Multigrid);
        if (lighter <= available)
        {
            message += " (with --set integrator.preconditioner=multigrid about " + gibibytes(lighter) + ")";
        }
    }
    throw InputError("size", message);
}
} // namespace masse::scene
