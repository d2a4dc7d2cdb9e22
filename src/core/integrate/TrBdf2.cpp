/// TR-BDF2 (Bank et al. 1985; Hosea and Shampine 1996): each step is the trapezoidal rule over the first g h, then
/// BDF2 through the step's start, that point and its end:
///     x_g = x_n + (g h / 2)(v_n + v_g),                 v_g = v_n + (g h / 2) M^-1 (f_n + f_g)
///     x_n+1 = x_g + c (x_g - x_n) + a v_n+1,           v_n+1 = v_g + c (v_g - v_n) + a M^-1 f_n+1
/// with c = (1 - g)^2 / (g (2 - g)) and a = (1 - g) h / (2 - g). Second order and L-stable for any g in (0, 1): the
/// stiff stretching modes are damped away as under BDF2, but the slow ones keep far more. For x'' = -w^2 x one step
/// multiplies the mode by R(i w h), R(z) = ((1 + c) (1 + g z / 2) / (1 - g z / 2) - c) / (1 - a z / h).
///
/// Why g = 0.82 and not the usual 2 - sqrt(2) (which makes both stages' matrices equal): at w h = 1 (6.3 steps a
/// period) 2 - sqrt(2) keeps 82% of an oscillator's amplitude over ten periods, period 3.9% long; g = 0.82 keeps 90.2%,
/// period 4.95% long (larger g keeps more and runs slower; the two bounds of 90% and 5% meet only between 0.818 and
/// 0.824). Both keep 99.9% of a sheet's swing (w h about 0.16) over 10 s where BDF2 keeps 90%, and at w h = 9 (the
/// Table 1 sheet's stretching) g = 0.82 multiplies a mode by 0.63 a step, 2 - sqrt(2) by 0.49, BDF2 by 0.50. The price
/// of unequal matrices: each stage keeps its own solve and preconditioner.
///
/// Each stage is ImplicitSolve's system (a, offset d, momentum m; see ImplicitSolve.h), with Newton corrections about
/// the latest iterate as in Bdf2.cpp until a correction moves no mass more than newtonTolerance:
///   trapezoid about (x_k, v_k): a = g h / 2, d = x_n + a v_n - x_k, m = v_n - v_k + a M^-1 f_n;
///   BDF2 about (x_k, v_k):      a as above, d = x_g + c (x_g - x_n) - x_k, m = v_g + c (v_g - v_n) - v_k.
/// A one-step method: no history, so a velocity changed between steps (a script, a grab) needs no care. Pinned masses
/// move by x += (stage length) v.
///
/// Contact: a step with velocity constraints (a mass resting on an obstacle or about to reach one) and the four steps
/// after it are BDF2's (Bdf2.cpp, with all its contact handling), continuing from the TR-BDF2 step before them; the
/// other steps are TR-BDF2's. A free sheet's motion is thus TR-BDF2's, and a sheet in contact moves as under bdf2.
///
/// Why BDF2 there: the trapezoidal stage reflects a stiff mode instead of damping it (its factor tends to -1), and
/// contact excites the stiff modes. With the constraints honoured in both stages as BDF2 honours them (each stage
/// placing constrained directions at its start + its length v, the speculative gaps and arrival speeds carried to the
/// second stage), the paper's drop scene diverges at 12x2x12 and the 6x2x6 sheet never comes to rest: a mass touching
/// the floor as it leaves it has no constraint, the trapezoidal stage carries it 5 cm into the floor and back out, and
/// the contact's projection puts it back each step, feeding the cycle. Left to the projection alone, the drop diverges
/// at the first contact. With BDF2 for the steps with constraints only, or for those and the one after, the drop
/// diverges at dt 0.02 (3x2x3 tipping over the block, in the BDF2 step after a TR-BDF2 one); from three steps on, all
/// twelve sizes from 3 to 16 keep the paper's order at dt 0.02, 0.025, 0.03 and 0.035.

#include "core/forces/Forces.h"
#include "core/integrate/Bdf2Integrator.h"
#include "core/integrate/ImplicitSolve.h"

#include <algorithm>
#include <limits>

namespace masse
{
namespace
{
/// g, the fraction of the step taken by the trapezoidal rule (see the file comment).
constexpr Real trapezoidFraction = 0.82;
/// Steps taken by BDF2 after the last with contact constraints, that one included (see the file comment): five BDF2
/// steps leave 3% of a mode at w h = 9 (the Table 1 sheet's stretching), which the contact's impulses excite.
constexpr int bdf2StepsAfterContact = 5;

class TrBdf2 final : public Integrator
{
public:
    explicit TrBdf2(const ImplicitSettings& settings)
        : m_trapezoid(settings, false), m_bdf2(settings, false), m_contactSteps(makeBdf2Integrator(settings))
    {
    }

    IntegratorStats step(MassSpringSystem& system, StepContext& context, Real h, const SubstepHints& hints) override
    {
        if (!context.constraints.empty())
        {
            m_stepsSinceContact = 0;
        }
        if (m_stepsSinceContact < bdf2StepsAfterContact)
        {
            ++m_stepsSinceContact;
            return m_contactSteps->step(system, context, h, hints);
        }
        Particles& p = system.particles;
        const std::size_t n = p.size();
        resize(n);
        const Real g = trapezoidFraction; // the file comment's g
        const Real trapezoidA = g * h / 2;
        const Real bdf2A = (1 - g) / (2 - g) * h;
        const Real c = (1 - g) * (1 - g) / (g * (2 - g));

        // Trapezoidal stage, from (x_n, v_n).
        evaluateForces(system, p.position, p.velocity, p.force);
        std::copy(p.position.begin(), p.position.end(), m_startPosition.begin());
        std::copy(p.velocity.begin(), p.velocity.end(), m_startVelocity.begin());
        for (std::size_t i = 0; i < n; ++i)
        {
            m_base[i] = m_startPosition[i] + trapezoidA * m_startVelocity[i];
            m_baseVelocity[i] =
                m_startVelocity[i] + (p.pinned[i] ? Vec3(Vec3::Zero()) : Vec3(trapezoidA / p.mass[i] * p.force[i]));
        }
        IntegratorStats stats = stage(system, m_trapezoid, trapezoidA, g * h, m_startPosition);

        // BDF2 stage, from (x_g, v_g) with (x_n, v_n) behind it.
        std::copy(p.position.begin(), p.position.end(), m_stagePosition.begin());
        for (std::size_t i = 0; i < n; ++i)
        {
            m_base[i] = m_stagePosition[i] + c * (m_stagePosition[i] - m_startPosition[i]);
            m_baseVelocity[i] = p.velocity[i] + c * (p.velocity[i] - m_startVelocity[i]);
        }
        evaluateForces(system, p.position, p.velocity, p.force);
        const IntegratorStats second = stage(system, m_bdf2, bdf2A, (1 - g) * h, m_stagePosition);
        stats.add(second);
        m_contactSteps->continueFrom(system, m_startPosition, m_startVelocity, h);
        return stats;
    }

    IntegratorKind kind() const override { return IntegratorKind::TrBdf2; }
    void setStageObserver(StageObserver* observer) override
    {
        m_trapezoid.setStageObserver(observer);
        m_bdf2.setStageObserver(observer);
    }
    bool honoursConstraints() const override { return true; }

private:
    void resize(std::size_t n)
    {
        for (std::vector<Vec3>* v :
             {&m_startPosition, &m_startVelocity, &m_stagePosition, &m_base, &m_baseVelocity, &m_offset, &m_momentum})
        {
            v->resize(n); // keeps its capacity: no allocation once the first step has run
        }
    }

    /// Solves one stage whose end is x = m_base + a v, v = m_baseVelocity + a M^-1 f(x, v), from the state in p (the
    /// stage's start `start`, forces evaluated there), `length` seconds long. Leaves the stage's end in p.
    IntegratorStats stage(MassSpringSystem& system, ImplicitSolve& solve, Real a, Real length,
                          const std::vector<Vec3>& start)
    {
        Particles& p = system.particles;
        const std::size_t n = p.size();
        IntegratorStats stats;
        Real correction = std::numeric_limits<Real>::infinity(); // the last correction's largest, m/s
        for (int iteration = 0; iteration <= maxNewtonIterations && correction * length > newtonTolerance; ++iteration)
        {
            if (iteration > 0)
            {
                evaluateForces(system, p.position, p.velocity, p.force);
            }
            for (std::size_t i = 0; i < n; ++i)
            {
                m_offset[i] = m_base[i] - p.position[i];
                m_momentum[i] = m_baseVelocity[i] - p.velocity[i];
            }
            const IntegratorStats solved = solve.solve(system, m_noConstraints, a, m_offset, m_momentum);
            stats.add(solved);
            const Real next = solve.largestDeltaV();
            if (!(next < correction))
            {
                break; // not converging: keep the last iterate
            }
            apply(p, solve, a, length, start);
            correction = next;
        }
        return stats;
    }

    /// Adds the solve's velocity change to p and places the masses: m_base + a v, but start + length v for pinned
    /// masses (a prescribed velocity moves them as it says).
    void apply(Particles& p, const ImplicitSolve& solve, Real a, Real length, const std::vector<Vec3>& start) const
    {
        for (std::size_t i = 0; i < p.size(); ++i)
        {
            p.velocity[i] += solve.deltaV(Index(i));
            p.position[i] = p.pinned[i] ? Vec3(start[i] + length * p.velocity[i]) : Vec3(m_base[i] + a * p.velocity[i]);
        }
    }

    ImplicitSolve m_trapezoid;
    ImplicitSolve m_bdf2;
    std::vector<Vec3> m_startPosition; ///< x_n
    std::vector<Vec3> m_startVelocity; ///< v_n
    std::vector<Vec3> m_stagePosition; ///< x_g
    std::vector<Vec3> m_base;          ///< the stage's end is m_base + a v
    std::vector<Vec3> m_baseVelocity;  ///< the stage's end velocity is m_baseVelocity + a M^-1 f
    std::vector<Vec3> m_offset;
    std::vector<Vec3> m_momentum;
    std::vector<VelocityConstraint> m_noConstraints;
    std::unique_ptr<Bdf2Integrator> m_contactSteps;  ///< the steps with contact
    int m_stepsSinceContact = bdf2StepsAfterContact; ///< steps since the last with constraints, counted to the limit
};
} // namespace

std::unique_ptr<Integrator> makeTrBdf2(const ImplicitSettings& settings)
{
    return std::make_unique<TrBdf2>(settings);
}
} // namespace masse
