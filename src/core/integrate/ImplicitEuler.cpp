/// Linearised backward Euler (Baraff and Witkin, "Large steps in cloth simulation", 1998): one Newton step of
/// v' = v + h M^-1 f(x + h v', v'), x' = x + h v'. The linear system and its solve are ImplicitSolve's (a = h).
///
/// Its numerical damping is strong: an undamped oscillator of frequency w loses amplitude by (1 + h^2 w^2)^(-1/2)
/// each step, which at the paper's step erases most of a sheet's swing (BDF2 keeps it, see Bdf2.cpp).

#include "core/forces/Forces.h"
#include "core/integrate/ImplicitSolve.h"

namespace masse
{
namespace
{
class ImplicitEuler final : public Integrator
{
public:
    explicit ImplicitEuler(const ImplicitSettings& settings) : m_solve(settings, true) {}

    IntegratorStats step(MassSpringSystem& system, StepContext& context, Real h, const SubstepHints& /*hints*/) override
    {
        Particles& p = system.particles;
        evaluateForces(system, p.position, p.velocity, p.force);
        const IntegratorStats stats = m_solve.solve(system, context.constraints, h, m_none, m_none);
        for (std::size_t i = 0; i < p.size(); ++i)
        {
            p.velocity[i] += m_solve.deltaV(Index(i));
            p.position[i] += h * p.velocity[i];
        }
        return stats;
    }

    IntegratorKind kind() const override { return IntegratorKind::ImplicitEuler; }
    void setStageObserver(StageObserver* observer) override { m_solve.setStageObserver(observer); }
    bool honoursConstraints() const override { return true; }

private:
    ImplicitSolve m_solve;
    const std::vector<Vec3> m_none;
};
} // namespace

std::unique_ptr<Integrator> makeImplicitEuler(const ImplicitSettings& settings)
{
    return std::make_unique<ImplicitEuler>(settings);
}
} // namespace masse
