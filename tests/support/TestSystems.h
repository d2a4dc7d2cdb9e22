#pragma once
// Small mass-spring systems with known analytic behaviour, shared by the physics tests.

#include "core/InputError.h"
#include "core/MassSpringSystem.h"
#include "core/Simulator.h"
#include "core/forces/Damping.h"
#include "core/forces/SimdPath.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <string>

namespace masse::test
{
/// Restores the SIMD path in use when it goes out of scope, however the test ends.
class SimdPathGuard
{
public:
    SimdPathGuard() : m_path(activeSimdPath()) {}
    ~SimdPathGuard() { setSimdPath(m_path); }
    SimdPathGuard(const SimdPathGuard&) = delete;
    SimdPathGuard& operator=(const SimdPathGuard&) = delete;

private:
    SimdPath m_path;
};

/// A straight chain along x: `count` masses of `mass` joined by springs of stiffness k and rest length `spacing`,
/// no damping, no gravity. The chain starts at rest at its rest length.
inline MassSpringSystem makeChain(int count, Real mass, Real stiffness, Real spacing, Real dampingCoefficient = 0)
{
    MassSpringSystem system;
    for (int i = 0; i < count; ++i)
    {
        system.particles.add(Vec3(Real(i) * spacing, 0, 0), mass);
    }
    for (int i = 0; i + 1 < count; ++i)
    {
        system.springs.add(Index(i), Index(i + 1), spacing, SpringClass::Planar);
        system.springs.mutableStiffness().back() = stiffness;
        system.springs.mutableDamping().back() = dampingCoefficient;
    }
    system.forces.gravity = Vec3::Zero();
    return system;
}

/// A 1 m chain of 41 masses of 1 g and 90.2 N/m springs (Table 1's) laid straight over 0.8 m between two pinned ends,
/// under gravity: it sags into a catenary, and its compressed springs make the implicit step buckle it at first.
inline MassSpringSystem makeChainPinnedStraight()
{
    MassSpringSystem chain = makeChain(41, 0.001, 90.2, 1.0 / 40);
    chain.forces.gravity = Vec3(0, -standardGravity, 0);
    for (int j = 0; j <= 40; ++j)
    {
        chain.particles.position[std::size_t(j)] = Vec3(0.8 * j / 40, 0, 0);
    }
    chain.particles.setPinned(0, true);
    chain.particles.setPinned(40, true);
    return chain;
}

/// The paper's Table 1 TRiMM sheet of N x 2 x N masses with its air damping; `latticeOut` receives its lattice.
inline MassSpringSystem paperSheet(int n, Lattice* latticeOut = nullptr)
{
    LatticeSpec spec;
    spec.countX = n;
    spec.countZ = n;
    const Lattice lattice = buildLattice(spec);
    if (latticeOut)
    {
        *latticeOut = lattice;
    }
    MassSpringSystem sheet = makeSheet(lattice, SheetParams{});
    sheet.forces.airDamping = airDampingRate(paperAirRetention, paperTimeStep);
    return sheet;
}

/// A two-layer TRiMM lattice of N x 2 x N masses over [-halfWidth, halfWidth] in x and z, its layers `thickness` apart.
inline Lattice twoLayerTrimm(int n, Real halfWidth, Real thickness)
{
    LatticeSpec spec;
    spec.structure = Structure::TRiMM;
    spec.countX = n;
    spec.layers = 2;
    spec.countZ = n;
    spec.minCorner = Vec3(-halfWidth, 0, -halfWidth);
    spec.maxCorner = Vec3(halfWidth, thickness, halfWidth);
    return buildLattice(spec);
}

/// The message of the InputError `action` throws, or "" if it throws none.
inline std::string inputErrorOf(const std::function<void()>& action)
{
    try
    {
        action();
    }
    catch (const InputError& e)
    {
        return e.what();
    }
    return "";
}

/// Simulates for `duration` seconds in steps of dt, calling observe(simulator) after every step.
template <typename Observer> void simulate(Simulator& simulator, Real duration, Real dt, Observer&& observe)
{
    const int steps = int(std::llround(duration / dt));
    for (int i = 0; i < steps; ++i)
    {
        simulator.step(dt);
        observe(simulator);
    }
}

/// Times at which a sampled signal crosses zero upward, by linear interpolation between samples.
class UpwardCrossings
{
public:
    void add(Real t, Real value)
    {
        if (m_hasPrevious && m_previous < 0 && value >= 0)
        {
            m_times.push_back(m_previousTime + (t - m_previousTime) * (-m_previous) / (value - m_previous));
        }
        m_previous = value;
        m_previousTime = t;
        m_hasPrevious = true;
    }
    /// Mean period from the first to the last crossing.
    Real meanPeriod() const { return (m_times.back() - m_times.front()) / Real(m_times.size() - 1); }
    std::size_t count() const { return m_times.size(); }

private:
    std::vector<Real> m_times;
    Real m_previous = 0;
    Real m_previousTime = 0;
    bool m_hasPrevious = false;
};
/// Whether two vectors of points hold the same bits (a -0 differs from a +0).
inline bool sameBits(const std::vector<Vec3>& a, const std::vector<Vec3>& b)
{
    return a.size() == b.size() &&
           std::equal(a.begin(), a.end(), b.begin(),
                      [](const Vec3& p, const Vec3& q) { return std::memcmp(p.data(), q.data(), sizeof(Vec3)) == 0; });
}
} // namespace masse::test
