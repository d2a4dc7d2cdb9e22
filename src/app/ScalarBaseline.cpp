#include "ScalarBaseline.h"

#include <chrono>
#include <cmath>
#include <vector>

namespace masse::app
{
double timeScalarBaseline(const MassSpringSystem& system, Real h, std::uint64_t substeps)
{
    std::vector<Vec3> x = system.particles.position;
    std::vector<Vec3> v = system.particles.velocity;
    std::vector<Vec3> f(x.size());
    const Particles& p = system.particles;
    const SpringSet& springs = system.springs;
    const Vec3 gravity = system.forces.gravity;
    const Real drag = system.forces.airDamping;
    const auto start = std::chrono::steady_clock::now();
    for (std::uint64_t step = 0; step < substeps; ++step)
    {
        for (std::size_t i = 0; i < x.size(); ++i)
        {
            f[i] = p.mass[i] * (gravity - drag * v[i]);
        }
        for (std::size_t s = 0; s < springs.size(); ++s)
        {
            const Index a = springs.ends()[s].a;
            const Index b = springs.ends()[s].b;
            const Vec3 d = x[a] - x[b];
            const Real length = d.norm();
            const Vec3 n = d / length;
            const Real magnitude = -(springs.stiffness()[s] * (length - springs.restLength()[s]) +
                                     springs.damping()[s] * (v[a] - v[b]).dot(n));
            f[a] += magnitude * n;
            f[b] -= magnitude * n;
        }
        for (std::size_t i = 0; i < x.size(); ++i)
        {
            v[i] += (h * p.inverseMass[i]) * f[i];
            x[i] += h * v[i];
        }
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    // Keep the result observable so the optimiser cannot drop the loop.
    volatile Real sink = x.empty() ? Real(0) : x[0].x();
    (void)sink;
    return seconds;
}
} // namespace masse::app
