#pragma once
// A flat mould for contact tests that need no Bullet.

#include "core/contact/Contact.h"

#include <optional>
#include <vector>

namespace masse::test
{
/// A flat, still mould surface: the half-space y < height, analytic, for contact without Bullet. Each mass within its
/// reach of the surface gets its plane.
class FlatMould final : public ContactDetector
{
public:
    explicit FlatMould(Real height) : m_height(height) {}
    int obstacleCount() const override { return 1; }
    void setTime(Real /*time*/) override {}
    void findContacts(const std::vector<Vec3>& x, const std::vector<Real>& reach, Real radius, Real /*dt*/,
                      ContactPlaneLists& lists) override
    {
        lists.resize(1);
        std::vector<ContactPlane>& out = lists[0];
        out.clear();
        for (std::size_t i = 0; i < x.size(); ++i)
        {
            if (x[i].y() - reach[i] - radius <= m_height)
            {
                ContactPlane plane;
                plane.mass = Index(i);
                plane.obstacle = 0;
                plane.face = 0;
                plane.normal = Vec3::UnitY();
                plane.offset = m_height;
                out.push_back(plane);
            }
        }
    }
    std::optional<SweepHit> sweep(const Vec3& from, const Vec3& to, Real radius) override
    {
        const Real start = from.y() - radius - m_height;
        const Real end = to.y() - radius - m_height;
        if (start >= 0 && end < 0)
        {
            return SweepHit{start / (start - end), Vec3::UnitY(), 0, 0};
        }
        return std::nullopt;
    }
    SurfaceDistance nearestSurface(const Vec3& x, Real maxDistance) override
    {
        const Real d = x.y() - m_height;
        return d > maxDistance ? SurfaceDistance{maxDistance, -1, -1} : SurfaceDistance{d, 0, 0};
    }
    Vec3 pointVelocity(int, const Vec3&, Real) override { return Vec3::Zero(); } // a static mould

private:
    Real m_height;
};
} // namespace masse::test
