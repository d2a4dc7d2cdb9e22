#include "StiffnessCalibration.h"

#include "BulletEnvironment.h"
#include "SoftBodyTwin.h"

#include "core/InputError.h"
#include "core/Simulator.h"

#include <cmath>

namespace masse::bridge
{
Real pbdLinearStiffness(Real stiffness, Real reducedMass, Real substep, int iterations)
{
    const Real load = stiffness * substep * substep / reducedMass; // k h^2 / mu, dimensionless
    return 1 - std::pow(1 + load, -Real(1) / Real(iterations));
}

Real pbdEquivalentStiffness(Real kLST, Real reducedMass, Real substep, int iterations)
{
    return reducedMass * (std::pow(1 - kLST, -Real(iterations)) - 1) / (substep * substep);
}

namespace
{
/// Largest drop below the starting heights, and which mass.
StaticSag sagOf(const std::vector<Vec3>& start, const std::vector<Vec3>& now)
{
    StaticSag sag;
    for (std::size_t i = 0; i < start.size(); ++i)
    {
        const Real drop = start[i].y() - now[i].y();
        if (drop > sag.sag)
        {
            sag.sag = drop;
            sag.mass = Index(i);
        }
    }
    return sag;
}

/// Steps `advance` window by window until the sag stops changing.
template <typename Advance, typename Positions>
StaticSag settle(const std::vector<Vec3>& start, Real dt, const SettleOptions& options, Advance&& advance,
                 Positions&& positions)
{
    const int stepsPerWindow = std::max(1, int(std::lround(options.window / dt)));
    StaticSag previous = sagOf(start, positions());
    Real elapsed = 0;
    while (elapsed < options.maxTime)
    {
        for (int s = 0; s < stepsPerWindow; ++s)
        {
            advance();
        }
        elapsed += Real(stepsPerWindow) * dt;
        StaticSag now = sagOf(start, positions());
        now.settleTime = elapsed;
        if (std::abs(now.sag - previous.sag) <= options.tolerance * std::max(now.sag, Real(1e-9)))
        {
            now.settled = true;
            return now;
        }
        previous = now;
    }
    return previous;
}

bool hasPins(const MassSpringSystem& sheet)
{
    for (std::uint8_t pinned : sheet.particles.pinned)
    {
        if (pinned)
        {
            return true;
        }
    }
    return false;
}
} // namespace

void clampOnTwoEdges(MassSpringSystem& sheet, const Lattice& lattice)
{
    const int last = lattice.layerCountX(0) - 1;
    for (int row = 0; row < lattice.layerCountZ(0); ++row)
    {
        sheet.particles.setPinned(lattice.index(0, row, 0), true);
        sheet.particles.setPinned(lattice.index(0, row, last), true);
    }
    sheet.markChanged();
}

StaticSag masseStaticSag(const MassSpringSystem& sheet, Real dt, const SettleOptions& options)
{
    MassSpringSystem system = sheet;
    system.forces.airDamping = options.airDamping;
    Simulator simulator(std::move(system), SimulatorSettings{});
    const std::vector<Vec3> start = sheet.particles.position;
    return settle(
        start, dt, options, [&] { simulator.step(dt); }, [&] { return simulator.system().particles.position; });
}

StaticSag twinStaticSag(const MassSpringSystem& sheet, Real dt, const SoftBodyTwinSettings& settings,
                        const SettleOptions& options)
{
    MassSpringSystem system = sheet;
    system.forces.airDamping = options.airDamping;
    const BulletEnvironment empty;
    SoftBodyTwin twin(system, empty, ContactSettings{}, dt, settings);
    const std::vector<Vec3> start = sheet.particles.position;
    return settle(
        start, dt, options, [&] { twin.step(); }, [&] { return twin.positions(); });
}

StiffnessCalibration calibrateLinearStiffness(const MassSpringSystem& sheet, Real dt, SoftBodyTwinSettings settings,
                                              Real tolerance, const SettleOptions& options)
{
    if (!hasPins(sheet))
    {
        throw InputError("calibration: the sheet needs pinned masses to hang from (clampOnTwoEdges pins a lattice's "
                         "edges)");
    }
    StiffnessCalibration result;
    result.masse = masseStaticSag(sheet, dt, options);
    // Search on s = -ln(1 - kLST): the static stiffness of a link grows like exp(n s), so the sag falls smoothly and
    // monotonically in s over the whole range, where in kLST itself all the action crowds next to 1.
    auto sagAt = [&](Real s)
    {
        settings.kLST = -std::expm1(-s);
        ++result.evaluations;
        return twinStaticSag(sheet, dt, settings, options);
    };
    Real lo = 1e-4; // kLST 1e-4: far softer than any sheet of interest
    Real hi = 40.0; // kLST 1 - 4e-18, which is 1 in double precision: rigid projection
    StaticSag atHi = sagAt(hi);
    if (atHi.sag > result.masse.sag)
    {
        result.kLST = 1;
        result.bullet = atHi;
        result.reachable = false;
        return result;
    }
    for (int i = 0; i < 80; ++i)
    {
        const Real mid = 0.5 * (lo + hi);
        const StaticSag atMid = sagAt(mid);
        result.kLST = *settings.kLST;
        result.bullet = atMid;
        if (std::abs(atMid.sag - result.masse.sag) <= tolerance * result.masse.sag)
        {
            break;
        }
        (atMid.sag > result.masse.sag ? lo : hi) = mid;
    }
    return result;
}
} // namespace masse::bridge
