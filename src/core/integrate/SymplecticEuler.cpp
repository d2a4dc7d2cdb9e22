/// Semi-implicit (symplectic) Euler: the velocity is updated first and moves the position. First order, but its
/// energy error stays bounded instead of drifting, which is why it is the default explicit integrator.

#include "core/forces/Forces.h"
#include "core/integrate/Integrator.h"
#include "core/parallel/TaskPool.h"

namespace masse
{
namespace
{
class SymplecticEuler final : public Integrator
{
public:
    IntegratorStats step(MassSpringSystem& system, StepContext& /*context*/, Real h, const SubstepHints& hints) override
    {
        Particles& p = system.particles;
        if (symplecticSubstep(system, h, hints.externalForces, hints.forcesRead))
        {
            return {};
        }
        evaluateForces(system, p.position, p.velocity, p.force);
        parallelFor(p.size(), massChunkSize,
                    [&](std::size_t begin, std::size_t end)
                    {
                        for (std::size_t i = begin; i < end; ++i)
                        {
                            p.velocity[i] += (h * p.inverseMass[i]) * p.force[i];
                            p.position[i] += h * p.velocity[i];
                        }
                    });
        return {};
    }
    IntegratorKind kind() const override { return IntegratorKind::SymplecticEuler; }
};
} // namespace

std::unique_ptr<Integrator> makeSymplecticEuler(const ImplicitSettings&)
{
    return std::make_unique<SymplecticEuler>();
}
} // namespace masse
