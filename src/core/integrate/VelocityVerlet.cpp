/// Velocity Verlet: x' = x + h v + h^2/2 a;  a' = a(x', v + h/2 a);  v' = v + h/2 (a + a').
/// Second order and symplectic for position-only forces. Damping forces need a velocity at x'; the half-step velocity
/// stands in for it, the usual choice. The force at the end of a step (in particles.force) is kept for the start of the
/// next, and recomputed when the system changed in between (see MassSpringSystem::revision).

#include "core/forces/Forces.h"
#include "core/integrate/Integrator.h"
#include "core/parallel/TaskPool.h"

namespace masse
{
namespace
{
class VelocityVerlet final : public Integrator
{
public:
    IntegratorStats step(MassSpringSystem& system, StepContext& /*context*/, Real h,
                         const SubstepHints& /*hints*/) override
    {
        Particles& p = system.particles;
        const std::size_t n = p.size();
        if (m_cachedSystem != &system || m_cachedRevision != system.revision || p.force.size() != n)
        {
            evaluateForces(system, p.position, p.velocity, p.force);
        }
        const Real halfStep = Real(0.5) * h;
        parallelFor(n, massChunkSize,
                    [&](std::size_t begin, std::size_t end)
                    {
                        for (std::size_t i = begin; i < end; ++i)
                        {
                            p.velocity[i] += (halfStep * p.inverseMass[i]) * p.force[i];
                            p.position[i] += h * p.velocity[i];
                        }
                    });
        evaluateForces(system, p.position, p.velocity, p.force);
        parallelFor(n, massChunkSize,
                    [&](std::size_t begin, std::size_t end)
                    {
                        for (std::size_t i = begin; i < end; ++i)
                        {
                            p.velocity[i] += (halfStep * p.inverseMass[i]) * p.force[i];
                        }
                    });
        m_cachedSystem = &system;
        m_cachedRevision = system.revision;
        return {};
    }
    IntegratorKind kind() const override { return IntegratorKind::VelocityVerlet; }

private:
    const MassSpringSystem* m_cachedSystem = nullptr;
    std::uint64_t m_cachedRevision = 0;
};
} // namespace

std::unique_ptr<Integrator> makeVelocityVerlet(const ImplicitSettings&)
{
    return std::make_unique<VelocityVerlet>();
}
} // namespace masse
