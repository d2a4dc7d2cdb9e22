#pragma once
/// BDF2 (Bdf2.cpp) as a part of another integrator: TR-BDF2 hands it the steps that have contact, and BDF2 needs the
/// state one step back, which TR-BDF2's steps made.

#include "core/integrate/Integrator.h"

#include <memory>
#include <vector>

namespace masse
{
/// Newton corrections after a step's first solve (a TR-BDF2 stage's too), at most: a tumbling sheet's step converges in
/// two.
constexpr int maxNewtonIterations = 4;
/// m: Newton stops once the largest velocity correction would move a mass less than this over the step.
constexpr Real newtonTolerance = 1e-6;

class Bdf2Integrator : public Integrator
{
public:
    /// The next step continues from a step of h that went from (previousPosition, previousVelocity) to the system's
    /// state now, whose velocities are what that step left (a change to them before the next step enters the history
    /// once, as after BDF2's own steps).
    virtual void continueFrom(const MassSpringSystem& system, const std::vector<Vec3>& previousPosition,
                              const std::vector<Vec3>& previousVelocity, Real h) = 0;
};

std::unique_ptr<Bdf2Integrator> makeBdf2Integrator(const ImplicitSettings& settings);
} // namespace masse
