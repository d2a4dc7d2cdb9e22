// obstacles[].type "box": `half_extents`, half its size along its own x, y and z.

#include "scene/shapes/BoxShape.h"

#include "scene/PlausibleRanges.h"

#include "core/Format.h"
#include "core/InputError.h"

#include <cmath>

namespace masse::scene
{
extern const ShapeEntry boxShape;

namespace
{
struct BoxSize
{
    Vec3 halfExtents; ///< m
};

std::any readBox(const JsonObject& o, const std::string& /*baseDirectory*/)
{
    const Vec3 half = o.vec3("half_extents");
    if (!(half.array() > 0).all())
    {
        o.fail("half_extents", "must be positive numbers of metres (got " + formatNumber(half.x()) + ", " +
                                   formatNumber(half.y()) + ", " + formatNumber(half.z()) + ")");
    }
    plausible::checkLength(o, "half_extents", half.maxCoeff());
    return BoxSize{half};
}

bridge::ObstacleShape boxSolidOf(const std::any& parameters, const std::string& /*obstacle*/)
{
    return boxSolid(std::any_cast<const BoxSize&>(parameters).halfExtents);
}

Real boxReach(const std::any& parameters)
{
    return std::any_cast<const BoxSize&>(parameters).halfExtents.norm();
}
} // namespace

bridge::ObstacleShape boxSolid(const Vec3& h)
{
    const char* axes[] = {"halfExtents.x", "halfExtents.y", "halfExtents.z"};
    for (int axis = 0; axis < 3; ++axis)
    {
        if (!(h[axis] > 0) || !std::isfinite(h[axis]))
        {
            throw InputError(axes[axis], "must be a positive number of metres (got " + formatNumber(h[axis]) + ")");
        }
    }
    bridge::ObstacleShape solid;
    solid.kind = bridge::SolidKind::Polyhedron;
    // Vertex k has x sign from bit 0, y from bit 1, z from bit 2.
    for (int k = 0; k < 8; ++k)
    {
        solid.polygons.vertices.emplace_back((k & 1) ? h.x() : -h.x(), (k & 2) ? h.y() : -h.y(),
                                             (k & 4) ? h.z() : -h.z());
    }
    solid.polygons.faces = {
        {1, 3, 7, 5}, // +x
        {0, 4, 6, 2}, // -x
        {2, 6, 7, 3}, // +y
        {0, 1, 5, 4}, // -y
        {4, 5, 7, 6}, // +z
        {0, 2, 3, 1}, // -z
    };
    return solid;
}

ShapeSpec boxShapeSpec(const Vec3& halfExtents)
{
    return {&boxShape, BoxSize{halfExtents}};
}

extern const ShapeEntry boxShape = {
    .name = "box",
    .closed = true,
    .read = readBox,
    .solid = boxSolidOf,
    .reach = boxReach,
};
} // namespace masse::scene
