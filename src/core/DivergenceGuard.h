#pragma once
/// Stops a run that has gone wrong before its state is used: after every step it checks, for every integrator,
///   - that every position and velocity is finite,
///   - that no free mass moves faster than a bound the scene derives from what can make it move (gravity and its
///     scripted motions, times a wide margin: a sound run stays far below it),
///   - that the sheet's mechanical energy (kinetic, gravity, springs, grab springs) has not grown beyond what was put
///     in: gravity is inside the energy; grab springs whose targets move, and models that change the springs (heat
///     softening them, a material's flow) add what they change the energy by; moving obstacles add at most their
///     contact force times their fastest speed. Dissipation is never credited back, so energy created by the numerics
///     shows up as soon as it exceeds a slack of a few percent of the sheet's energy scale.
/// A breach throws NumericalError with the time, the mass, the quantity and what to try instead.

#include "MassSpringSystem.h"

#include <limits>
#include <stdexcept>
#include <string>

namespace masse
{
/// Thrown when the state stops being sound (a diverged run); the message says when, where and what to try.
class NumericalError : public std::runtime_error
{
public:
    explicit NumericalError(const std::string& message) : std::runtime_error(message) {}
};

struct GuardSettings
{
    bool enabled = true;
    /// m/s; no free mass may move faster (infinity: no bound). A scene sets it from its gravity, air, room and script.
    Real speedLimit = std::numeric_limits<Real>::infinity();
    /// m/s, the fastest any moving obstacle's surface moves (0: all static); bounds the work contact can do.
    Real obstacleSpeed = 0;
    /// Energy may exceed what was put in by this fraction of the sheet's energy scale (its weight times its size,
    /// plus what was put in): room for integration and contact-projection error, far below a blow-up.
    Real energySlack = 0.05;
    /// The energy account is opt-in: with the slack above it also stopped sound runs (explicit Euler's own energy
    /// error in free fall at 0.03 s, a hanging chain released under the implicit integrator), so until its slack is
    /// derived from each integrator's error it runs only where a caller asks for it; the finite and speed checks
    /// always run.
    bool checkEnergy = false;
};

/// The mechanical energy of a sheet (J): kinetic and gravity of its free masses, its springs, its grab springs.
Real mechanicalEnergy(const MassSpringSystem& system);

class DivergenceGuard
{
public:
    void setSettings(const GuardSettings& settings) { m_settings = settings; }
    const GuardSettings& settings() const { return m_settings; }

    /// Around every pass of the step hooks (which may move grab targets, change gravity, pins or the springs):
    /// what they change the energy by is energy put in.
    void beforeHooks(const MassSpringSystem& system);
    void afterHooks(const MassSpringSystem& system);

    /// At the end of every step of dt seconds ending at `time`, with the mean contact force on each mass over the
    /// step (nullptr without contact). Throws NumericalError on a breach.
    void check(const MassSpringSystem& system, Real time, Real dt, const std::vector<Vec3>* contactForce);

    /// J: energy put in so far, and the energy at the start of the accounting.
    Real energyPutIn() const { return m_putIn; }
    Real referenceEnergy() const { return m_reference; }

private:
    [[noreturn]] void fail(Real time, const std::string& what) const;
    /// Energy of the grab springs only (cheap: there are few).
    static Real grabEnergy(const MassSpringSystem& system);

    GuardSettings m_settings;
    bool m_started = false;
    Real m_reference = 0; ///< J, energy when the accounting (re)started
    Real m_putIn = 0;     ///< J, put in since then
    Real m_scale = 0;     ///< J, the sheet's weight times its size
    bool m_inStep = false;
    Real m_lastGrabEnergy = 0;
    std::uint64_t m_lastRevision = 0;
    // Within a hooks pass.
    std::uint64_t m_hooksRevision = 0;
    Real m_hooksGrabEnergy = 0;
    Real m_hooksEnergy = 0;
    bool m_hooksMeasured = false; ///< the full energy was measured before the pass
    /// Some hook changes the springs every pass (a material model): measure the full energy around every pass.
    bool m_measureEveryPass = false;
    bool m_rebase = false; ///< an unmeasured change happened: restart the accounting at the end of this step
};
} // namespace masse
