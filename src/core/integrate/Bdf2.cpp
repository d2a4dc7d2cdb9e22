/// BDF2, the second-order backward differentiation formula (Choi and Ko, "Stable but responsive cloth", 2002):
///     x_n+1 = 4/3 x_n - 1/3 x_n-1 + 2/3 h v_n+1,    v_n+1 = 4/3 v_n - 1/3 v_n-1 + 2/3 h M^-1 f(x_n+1, v_n+1).
/// One Newton step about (x_n, v_n) is backward Euler's system with the step a = 2h/3, a position offset
/// d = (x_n - x_n-1)/3 and a momentum term (v_n - v_n-1)/3 (see ImplicitSolve.h). Like backward Euler it is stable
/// at any step, but its numerical damping is of higher order: at w h = 1 an oscillator keeps most of its amplitude
/// over ten periods where backward Euler keeps a few per cent.
///
/// Choi and Ko take that one Newton step. Here Newton goes on (at most maxNewtonIterations corrections, each the same
/// solve about the latest iterate) until the correction moves no mass more than newtonTolerance over the step: a
/// single linearised step moves every mass of a rotating sheet along its tangent, and the sheet's stiff springs then
/// take the stretch out of the rotation. Measured on a Table 1 sheet tumbling at 7.8 rad/s (the drop scene's tipping
/// over the block's edge, 0.23 rad a step): one step leaves 1.45 rad/s after ten steps, Newton 7.34
/// (Bdf2.TumblingSheetKeepsItsSpin). A free fall or a small oscillation is linear and takes one correction of about
/// zero: one more solve a step.
///
/// The first step (and the first after the number of masses changes) has no history and is a backward Euler step.
/// Contact is handled like backward Euler's (velocity constraints through the solve's filter); in a mass's
/// constrained directions the position follows x += h v, so a prescribed velocity moves it exactly as it would under
/// backward Euler and the history cannot push it into an obstacle, and the solve places it there too
/// (HeldPlacement). Pinned masses move by x += h v likewise. A velocity change between steps (the contact's impulses)
/// enters the history as it happened, once (see step()), and the contact's projection moves a mass by 2h/3 of the
/// velocity it changes (StepContext::moveStep), as this step placed it.

#include "core/forces/Forces.h"
#include "core/integrate/Bdf2Integrator.h"
#include "core/integrate/ImplicitSolve.h"

#include <algorithm>
#include <limits>

namespace masse
{
namespace
{
class Bdf2 final : public Bdf2Integrator
{
public:
    // Speculative constraints as backward Euler's, friction capped at Coulomb's within each solve, and resting
    // constraints that pull released (ImplicitSolve.h: capFriction, releaseLifting). Left to the contact's projection
    // instead, arriving masses would be stopped after the solve, while the masses joined to them move as if they
    // went on: 0.045 J in the 3x2x3 drop's springs at landing (symplectic 0.008 J), and the drop's wedge after the
    // floor at 9x2x9. The speculative constraints need the solve to place constrained masses where BDF2 puts them
    // (HeldPlacement in ImplicitSolve.h) and the contact's impulses kept out of the extrapolation (step()); without
    // that they put energy into landings (6x2x6: 0.67 J in one step).
    explicit Bdf2(const ImplicitSettings& settings) : m_solve(settings, true, true, true) {}

    IntegratorStats step(MassSpringSystem& system, StepContext& context, Real h, const SubstepHints& /*hints*/) override
    {
        Particles& p = system.particles;
        const std::size_t n = p.size();
        const bool history = m_historySystem == &system && m_previousPosition.size() == n && m_previousStep == h;
        evaluateForces(system, p.position, p.velocity, p.force);
        IntegratorStats stats;
        if (!history)
        {
            stats = m_solve.solve(system, context.constraints, h, m_none, m_none);
            m_previousPosition = p.position; // sized once; later steps copy into the same storage
            m_previousVelocity = p.velocity;
            resizeWork(n);
            for (std::size_t i = 0; i < n; ++i)
            {
                p.velocity[i] += m_solve.deltaV(Index(i));
                p.position[i] += h * p.velocity[i];
            }
        }
        else
        {
            const Real a = Real(2) / Real(3) * h;
            // What changed a velocity since the last solve (the contact's impulses, a script) happened once: it is
            // moved into the history too, so that BDF2 does not extrapolate it as an acceleration into this step.
            for (std::size_t i = 0; i < n; ++i)
            {
                m_previousVelocity[i] += p.velocity[i] - m_solvedVelocity[i];
                m_offset[i] = (p.position[i] - m_previousPosition[i]) / Real(3);
                m_momentum[i] = (p.velocity[i] - m_previousVelocity[i]) / Real(3);
            }
            stats = m_solve.solve(system, context.constraints, a, m_offset, m_momentum, {h, nullptr});
            std::copy(p.position.begin(), p.position.end(), m_previousPosition.begin());
            std::copy(p.velocity.begin(), p.velocity.end(), m_previousVelocity.begin());
            applyCorrection(p, h, a);
            context.moveStep = a;
            Real correction = std::numeric_limits<Real>::infinity(); // the last Newton correction's largest, m/s
            for (int iteration = 0; iteration < maxNewtonIterations && correction * h > newtonTolerance; ++iteration)
            {
                // Newton on the BDF2 system about the current iterate (x_k, v_k): the step ends at
                // x_n + d + a v', so the solve's offset from x_k is x_n + d - x_k, and its momentum term is
                // v_n + m - v_k (ImplicitSolve.h with the iterate as the current state).
                for (std::size_t i = 0; i < n; ++i)
                {
                    m_newtonOffset[i] = m_previousPosition[i] + m_offset[i] - p.position[i];
                    m_newtonMomentum[i] = m_previousVelocity[i] + m_momentum[i] - p.velocity[i];
                    m_newtonStart[i] = m_previousPosition[i] - p.position[i];
                }
                evaluateForces(system, p.position, p.velocity, p.force);
                const IntegratorStats more = m_solve.solve(system, context.constraints, a, m_newtonOffset,
                                                           m_newtonMomentum, {h, &m_newtonStart});
                stats.add(more);
                const Real next = m_solve.largestDeltaV();
                if (!(next < correction))
                {
                    break; // not converging (contact changing under the iteration): keep the last iterate
                }
                applyCorrection(p, h, a);
                correction = next;
            }
            // The solve's reactions are the constraints' forces times a. A reaction is the force times the step
            // (VelocityConstraint.h): the contact sizes the next frame's friction from it, and reports it. Left at a,
            // the friction would be 2/3 of Coulomb's (a sheet on a 30 degree slope sliding at 3.17 m/s^2, not 2.36).
            for (VelocityConstraint& c : context.constraints)
            {
                c.reaction *= Real(1.5); // h / a
            }
        }
        std::copy(p.velocity.begin(), p.velocity.end(), m_solvedVelocity.begin());
        m_historySystem = &system;
        m_previousStep = h;
        return stats;
    }

    IntegratorKind kind() const override { return IntegratorKind::Bdf2; }
    void setStageObserver(StageObserver* observer) override { m_solve.setStageObserver(observer); }
    bool honoursConstraints() const override { return true; }

    void continueFrom(const MassSpringSystem& system, const std::vector<Vec3>& previousPosition,
                      const std::vector<Vec3>& previousVelocity, Real h) override
    {
        resizeWork(system.particles.size());
        m_previousPosition = previousPosition; // copies into the storage it has
        m_previousVelocity = previousVelocity;
        std::copy(system.particles.velocity.begin(), system.particles.velocity.end(), m_solvedVelocity.begin());
        m_historySystem = &system;
        m_previousStep = h;
    }

private:
    void resizeWork(std::size_t n)
    {
        for (std::vector<Vec3>* v :
             {&m_offset, &m_momentum, &m_newtonOffset, &m_newtonMomentum, &m_newtonStart, &m_solvedVelocity})
        {
            v->resize(n);
        }
    }

    /// Adds the last solve's velocity change to p and places the masses from it.
    void applyCorrection(Particles& p, Real h, Real a) const
    {
        for (std::size_t i = 0; i < p.size(); ++i)
        {
            p.velocity[i] += m_solve.deltaV(Index(i));
        }
        place(p, h, a);
    }

    /// The step's end positions from the velocities in p, its start in m_previousPosition and the offset d:
    /// x_n + d + a v, but x_n + h v for pinned masses and in each mass's constrained directions.
    void place(Particles& p, Real h, Real a) const
    {
        for (std::size_t i = 0; i < p.size(); ++i)
        {
            const Vec3 bdf2Move = m_offset[i] + a * p.velocity[i];
            const Vec3 eulerMove = h * p.velocity[i];
            if (p.pinned[i])
            {
                p.position[i] = m_previousPosition[i] + eulerMove;
            }
            else if (m_solve.constrained())
            {
                const Mat3 held = m_solve.held(Index(i));
                p.position[i] = m_previousPosition[i] + (bdf2Move + held * (eulerMove - bdf2Move));
            }
            else
            {
                p.position[i] = m_previousPosition[i] + bdf2Move;
            }
        }
    }

    ImplicitSolve m_solve;
    const std::vector<Vec3> m_none;
    std::vector<Vec3> m_previousPosition;
    std::vector<Vec3> m_previousVelocity;
    std::vector<Vec3> m_solvedVelocity; ///< the velocities the last step's solve left
    std::vector<Vec3> m_offset;
    std::vector<Vec3> m_momentum;
    std::vector<Vec3> m_newtonOffset;
    std::vector<Vec3> m_newtonMomentum;
    std::vector<Vec3> m_newtonStart;
    const MassSpringSystem* m_historySystem = nullptr;
    Real m_previousStep = 0;
};
} // namespace

std::unique_ptr<Bdf2Integrator> makeBdf2Integrator(const ImplicitSettings& settings)
{
    return std::make_unique<Bdf2>(settings);
}

std::unique_ptr<Integrator> makeBdf2(const ImplicitSettings& settings)
{
    return makeBdf2Integrator(settings);
}
} // namespace masse
