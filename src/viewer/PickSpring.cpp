#include "PickSpring.h"

#include "core/integrate/StabilityEstimate.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace masse::viewer
{
UserSpring makePickSpring(const MassSpringSystem& system, Index mass, const Vec3& target,
                          const PickSpringTuning& tuning)
{
    // The highest frequency does not depend on the integrator; the kind only decides the step derived from it.
    const Real sheetFrequency = estimateStability(system, IntegratorKind::SymplecticEuler, Real(1)).highestFrequency;
    const Real picked = system.particles.mass[mass];
    const Real frequency = tuning.frequencyFraction * sheetFrequency;
    const std::vector<Real>& masses = system.particles.mass;
    const Real sheetMass = std::accumulate(masses.begin(), masses.end(), Real(0));
    const Real gravity = std::max(system.forces.gravity.norm(), standardGravity);

    UserSpring spring;
    spring.mass = mass;
    spring.target = target;
    spring.stiffness = picked * frequency * frequency;
    spring.damping = Real(2) * tuning.dampingRatio * std::sqrt(spring.stiffness * picked);
    spring.maxForce = tuning.maxForceInSheetWeights * sheetMass * gravity;
    return spring;
}
} // namespace masse::viewer
