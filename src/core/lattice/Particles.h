#pragma once
/// Per-mass state of a sheet, as parallel arrays (structure of arrays) so kernels walk them linearly.

#include "core/Types.h"

#include <vector>

namespace masse
{
struct Particles
{
    std::vector<Vec3> position;      ///< m
    std::vector<Vec3> velocity;      ///< m/s
    std::vector<Vec3> force;         ///< N, total force of the last evaluation
    std::vector<Vec3> externalForce; ///< N, applied by the user or a script, kept until changed
    std::vector<Real> mass;          ///< kg
    std::vector<Real> inverseMass;   ///< 1/kg; 0 for a pinned mass, so integrators need no special case
    std::vector<std::uint8_t> pinned;

    std::size_t size() const { return position.size(); }

    /// Appends a free mass at rest and returns its index.
    Index add(const Vec3& x, Real m)
    {
        position.push_back(x);
        velocity.push_back(Vec3::Zero());
        force.push_back(Vec3::Zero());
        externalForce.push_back(Vec3::Zero());
        mass.push_back(m);
        inverseMass.push_back(Real(1) / m);
        pinned.push_back(0);
        return Index(position.size() - 1);
    }

    /// A pinned mass keeps its position and has zero velocity until it is unpinned.
    void setPinned(Index i, bool isPinned)
    {
        pinned[i] = isPinned ? 1 : 0;
        inverseMass[i] = isPinned ? Real(0) : Real(1) / mass[i];
        if (isPinned)
        {
            velocity[i].setZero();
        }
    }
};
} // namespace masse
