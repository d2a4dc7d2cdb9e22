#pragma once
/// Stops a run that has gone wrong before its state is used: after every step it checks, for every integrator,
///   - that every position and velocity is finite,
///   - that no free mass moves faster than a bound the scene derives from what can make it move (gravity and its
///     scripted motions, times a wide margin: a sound run stays far below it),
///   - that the sheet's mechanical energy (kinetic, gravity, springs, grab springs) has not grown beyond what was put
///     in: gravity is inside the energy; grab springs whose targets move, and models that change the springs (heat
///     softening them, a material's flow) add what they change the energy by; moving obstacles add at most their
///     contact force times their fastest speed; applied forces (pressure loads, scripted forces) add at most their
///     size times how far their masses moved; the contact solver adds what putting masses back on a surface stores
///     (see afterContact). Dissipation is never credited back, so energy created by the numerics shows up as soon as
///     it exceeds the integrator's own known error plus a slack of a fraction of the sheet's energy scale.
/// The integrator's own error: explicit Euler gains h^2 |f|^2 / (2 m) per substep on every mass under a steady
/// force f (exactly so in free fall: 1/2 m g^2 h per second), which no damping of the springs takes back; the guard
/// adds twice that for gravity, applied forces and grabs. The implicit integrators minimise a quadratic model of the
/// springs' energy; what the true springs hold beyond it after a substep (a compressed chain buckling) is their
/// error, which they damp within a few steps: the guard allows it, halved every substep. The symplectic
/// integrators' error is bounded (it oscillates, of order h): the fraction of the energy scale covers it.
/// Material sheets weigh the energy of motion only (EnergyAccount::Motion). What the hooks change is credited only as
/// potential energy: no hook gives masses speed.
/// A breach throws NumericalError with the time, the mass, the quantity and what to try instead.

#include "core/MassSpringSystem.h"
#include "core/NumericalError.h"
#include "core/integrate/Integrator.h"

#include <limits>
#include <stdexcept>
#include <string>

namespace masse
{
/// Which energies the account weighs against what was put in.
enum class EnergyAccount
{
    /// Kinetic, gravity, the sheet's springs and the grabs.
    Mechanical,
    /// Kinetic, gravity and the grabs, against the same budget (which holds the springs' energy at the start and what
    /// the hooks changed it by): for material sheets. A glassy sheet's springs (meganewtons per metre) store hundreds
    /// of times the sheet's weight times its size when the contact moves a layer back by a millimetre (152 J on a
    /// 0.2 J PET sheet, measured), energy the implicit step damps within the step, as stiff springs' is, and which
    /// never shows as motion; a blow-up does (a sheet flung up, or faster than anything drives it). Cheaper too: no
    /// spring pass at the check.
    Motion,
};

struct GuardSettings
{
    bool enabled = true;
    /// m/s; no free mass may move faster (infinity: no bound). A scene sets it from its gravity, air, room and script.
    Real speedLimit = std::numeric_limits<Real>::infinity();
    /// m/s, the fastest any moving obstacle's surface moves (0: all static); bounds the work contact can do.
    Real obstacleSpeed = 0;
    /// Energy may exceed what was put in, and the integrator's known error, by this fraction of the sheet's energy
    /// scale (its weight times its size, plus the kinetic and elastic energy it started with, plus what was put in):
    /// room for integration and contact-projection error, far below a blow-up (which grows by orders of magnitude).
    Real energySlack = 0.25;
    /// The energy account (the finite and speed checks always run when the guard is enabled).
    bool checkEnergy = true;
    EnergyAccount account = EnergyAccount::Mechanical;
};

/// The step the guard checks: when it ended, how it was taken, and the contact it had.
struct GuardStep
{
    Real time = 0;    ///< s, at the end of the step
    Real dt = 0;      ///< s
    Real substep = 0; ///< s, the integrator's substep h
    IntegratorKind integrator = IntegratorKind::ImplicitEuler;
    /// N, the mean contact force on each mass over the step; nullptr without contact.
    const std::vector<Vec3>* contactForce = nullptr;
};

/// The mechanical energy of a sheet (J): kinetic and gravity of its free masses, its springs, its grab springs.
Real mechanicalEnergy(const MassSpringSystem& system);
/// The sheet's energy of motion (J): kinetic and gravity of its free masses and its grab springs (no sheet springs).
Real motionEnergy(const MassSpringSystem& system);

class DivergenceGuard
{
public:
    void setSettings(const GuardSettings& settings) { m_settings = settings; }
    const GuardSettings& settings() const { return m_settings; }

    /// Around every pass of the step hooks (which may move grab targets, change gravity, pins or the springs):
    /// what they change the energy by is energy put in. The first pass of a step also takes in what changed since
    /// the last step from outside (a viewer's pick, a pin).
    void beforeHooks(const MassSpringSystem& system);
    void afterHooks(const MassSpringSystem& system);

    /// Around every integrator substep: before the integrator, after it (the implicit integrators' known
    /// linearisation error), and after the contact solver's pass that follows it (see afterContact).
    void beforeSubstep(const MassSpringSystem& system, IntegratorKind integrator);
    void afterIntegrator(const MassSpringSystem& system, IntegratorKind integrator);
    /// The contact solver puts masses that went into an obstacle back on its surface. At the implicit integrators'
    /// long steps a fast landing goes deep (8 m/s for 0.03 s is 0.24 m), and putting a two-layer sheet back flattens
    /// its layers onto the surface, which stores energy in the compressed springs between them (3 J from a fall of
    /// 2 J, measured). Energy the pass adds is put in when no mass was moved farther than it travelled in the
    /// substep (plus a millimetre): the contact undid a move, as a stiff obstacle would. A pass that throws masses
    /// farther than they came (a contact radius of a kilometre) is not credited, and its energy is a breach. Measured
    /// for the implicit integrators only: the explicit ones' substeps are short, their penetrations small.
    void afterContact(const MassSpringSystem& system, IntegratorKind integrator);

    /// After the integrator's first substep of a step, before the contact pass: the speed bound of check(). A move the
    /// arithmetic cannot resolve (a gravity of 1e100 m/s^2 carries a mass 1e94 m in a millisecond) is put back by the
    /// contact, at rest, at a place that is on no surface (the sheet flat at y = 0, the floor at -2.81 m), and would
    /// pass every check at the step's end. Throws NumericalError on a breach.
    void checkSpeedBeforeContact(const MassSpringSystem& system, const GuardStep& step);
    /// At the end of every step. Throws NumericalError on a breach.
    void check(const MassSpringSystem& system, const GuardStep& step);

    /// J: energy put in so far, the energy at the start of the accounting, and the integrator's known error allowed.
    Real energyPutIn() const { return m_putIn; }
    Real referenceEnergy() const { return m_reference; }
    Real integratorAllowance() const { return m_integratorError + m_linearisationError; }

private:
    [[noreturn]] void fail(const GuardStep& step, const std::string& what) const;
    /// The energy the account weighs (settings().account).
    Real accountedEnergy(const MassSpringSystem& system) const;
    /// The accounted energy at a step's start: the last check's when the system has not been marked changed since
    /// (MassSpringSystem::revision: pins, teleported masses and new coefficients mark it), with the grabs' energy now.
    Real energyBetweenSteps(const MassSpringSystem& system) const;
    /// mechanicalEnergy with the same bits, its spring pass taken from m_springMemo when that holds.
    Real mechanical(const MassSpringSystem& system) const;
    /// J, what the hooks may put in is what they change the account's potential energy by (springs softened or
    /// stiffened by heat or a material's flow, gravity, pins, grab targets): no hook gives masses speed, so one that
    /// does (a fault) is not credited and its energy is a breach.
    Real hooksEnergy(const MassSpringSystem& system) const;

    /// The springs' energy last measured, with the positions (bit for bit) and the revision it was measured at. The
    /// springs' energy is the guard's costliest figure (a pass over every spring), and it is asked for again at the
    /// same state: after a contact pass or a hook that moved nothing, and on both sides of every hook pass of a
    /// material scene. Coefficients change only with the revision (MassSpringSystem::markChanged).
    struct SpringEnergyMemo
    {
        bool valid = false;
        std::uint64_t revision = 0;
        std::size_t springs = 0;
        std::vector<Vec3> positions;
        Real energy = 0;

        bool holds(const MassSpringSystem& system) const;
        void keep(const MassSpringSystem& system, Real springEnergy);
    };
    mutable SpringEnergyMemo m_springMemo;

    GuardSettings m_settings;
    bool m_started = false;
    Real m_reference = 0;       ///< J, energy when the accounting (re)started
    Real m_putIn = 0;           ///< J, put in since then
    Real m_scale = 0;           ///< J, the sheet's weight times its size plus its starting kinetic and elastic energy
    Real m_lastEnergy = 0;      ///< J, at the end of the last step
    Real m_lastGrabEnergy = 0;  ///< J, the grabs' part of it
    Real m_integratorError = 0; ///< J, explicit Euler's known gain since the accounting started
    /// J, the implicit integrators' recent linearisation error: what each substep's spring energy exceeds its linear
    /// model by, halved every substep (the integrator damps what it put into stiff springs within a few steps).
    Real m_linearisationError = 0;
    std::vector<Vec3> m_stepStart;    ///< m, positions at the start of the step (the work of applied forces)
    std::vector<Real> m_gapPartial;   ///< the linearisation gap's chunk sums (kept to allocate nothing a step)
    std::vector<Vec3> m_substepStart; ///< m, positions at the start of the substep (implicit integrators only)
    std::vector<Vec3> m_contactStart; ///< m, positions before the contact pass (implicit integrators only)
    Real m_contactEnergy = 0;         ///< J, energy before the contact pass
    bool m_inStep = false;
    std::uint64_t m_lastRevision = 0;
    // Within a hooks pass.
    std::uint64_t m_hooksRevision = 0;
    Real m_hooksGrabEnergy = 0;
    Real m_hooksEnergy = 0;
    bool m_hooksMeasured = false; ///< the full energy was measured before the pass
    /// Some hook changes the springs or pins every pass (a material model, a script): measure the full energy around
    /// every pass. On for the first step, off after it if no hook changed anything in it.
    bool m_measureEveryPass = true;
    bool m_changedInFirstStep = false;
    bool m_measureDecided = false;
    bool m_rebase = false; ///< an unmeasured change happened: restart the accounting at the end of this step
};
} // namespace masse
