#pragma once
/// Springs from a mass to a moving point: the paper's dynamic spring for mouse picking (section 7), and scripted
/// drags. They are added and removed between steps; an id stays valid until its spring is removed.

#include "core/Types.h"

#include <limits>
#include <vector>

namespace masse
{
using UserSpringId = std::uint32_t;

struct UserSpring
{
    Index mass = 0;
    Vec3 target = Vec3::Zero();         ///< m, the point the mass is pulled toward
    Vec3 targetVelocity = Vec3::Zero(); ///< m/s, damping acts on the mass's velocity relative to this
    Real stiffness = 0;                 ///< N/m
    Real damping = 0;                   ///< N s/m
    /// N. The pull is capped, as Box2D's mouse joint is, so a far cursor cannot inject an unbounded force.
    Real maxForce = std::numeric_limits<Real>::infinity();
};

class UserSprings
{
public:
    UserSpringId add(const UserSpring& spring)
    {
        m_springs.push_back(spring);
        m_ids.push_back(m_nextId);
        return m_nextId++;
    }

    /// Returns false when no spring has that id (already removed).
    bool remove(UserSpringId id)
    {
        for (std::size_t i = 0; i < m_ids.size(); ++i)
        {
            if (m_ids[i] == id)
            {
                m_springs.erase(m_springs.begin() + std::ptrdiff_t(i));
                m_ids.erase(m_ids.begin() + std::ptrdiff_t(i));
                return true;
            }
        }
        return false;
    }

    UserSpring* find(UserSpringId id)
    {
        for (std::size_t i = 0; i < m_ids.size(); ++i)
        {
            if (m_ids[i] == id)
            {
                return &m_springs[i];
            }
        }
        return nullptr;
    }

    const std::vector<UserSpring>& all() const { return m_springs; }
    std::size_t size() const { return m_springs.size(); }

private:
    std::vector<UserSpring> m_springs;
    std::vector<UserSpringId> m_ids;
    UserSpringId m_nextId = 1;
};

/// Force on the mass at x moving at v, and the stiffness the implicit solver should use (lower while capped).
struct UserSpringForce
{
    Vec3 force;
    Real effectiveStiffness;
};

inline UserSpringForce evaluateUserSpring(const UserSpring& spring, const Vec3& x, const Vec3& v)
{
    Vec3 force = -spring.stiffness * (x - spring.target) - spring.damping * (v - spring.targetVelocity);
    Real stiffness = spring.stiffness;
    const Real magnitude = force.norm();
    if (magnitude > spring.maxForce)
    {
        const Real scale = spring.maxForce / magnitude;
        force *= scale;
        stiffness *= scale;
    }
    return {force, stiffness};
}
} // namespace masse
