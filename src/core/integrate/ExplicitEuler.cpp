/// The paper's integrator: both updates use the state at the start of the step. It adds energy to every undamped
/// oscillation, so the stability estimate gives it much smaller substeps than the symplectic integrators.

#include "core/forces/Forces.h"
#include "core/integrate/Integrator.h"
#include "core/parallel/TaskPool.h"

namespace masse
{
namespace
{
class ExplicitEuler final : public Integrator
{
public:
    IntegratorStats step(MassSpringSystem& system, StepContext& /*context*/, Real h,
                         const SubstepHints& /*hints*/) override
    {
        Particles& p = system.particles;
        evaluateForces(system, p.position, p.velocity, p.force);
        parallelFor(p.size(), massChunkSize,
                    [&](std::size_t begin, std::size_t end)
                    {
                        for (std::size_t i = begin; i < end; ++i)
                        {
                            p.position[i] += h * p.velocity[i];
                            p.velocity[i] += (h * p.inverseMass[i]) * p.force[i];
                        }
                    });
        return {};
    }
    IntegratorKind kind() const override { return IntegratorKind::ExplicitEuler; }
};
} // namespace

std::unique_ptr<Integrator> makeExplicitEuler(const ImplicitSettings&)
{
    return std::make_unique<ExplicitEuler>();
}
} // namespace masse
