// obstacles[].type "prism": `width`, `height`, `length` and `apex`, the triangle and its extrusion of PrismShape.h.

#include "scene/shapes/PrismShape.h"

#include "scene/PlausibleRanges.h"

#include "core/Format.h"
#include "core/InputError.h"

#include <cmath>

namespace masse::scene
{
namespace
{
/// A length that must be > 0 (the key is required).
Real prismLength(const JsonObject& o, const std::string& key)
{
    const Real value = o.number(key);
    if (!(value > 0))
    {
        o.fail(key, "must be a positive number of metres (got " + formatNumber(value) + ")");
    }
    plausible::checkLength(o, key, value);
    return value;
}

std::any readPrism(const JsonObject& o, const std::string& /*baseDirectory*/)
{
    PrismSize size;
    size.width = prismLength(o, "width");
    size.height = prismLength(o, "height");
    size.length = prismLength(o, "length");
    size.apex = o.number("apex", 0.0);
    plausible::checkPoint(o, "apex", Vec3(size.apex, 0, 0));
    return size;
}

bridge::ObstacleShape prismSolidOf(const std::any& parameters, const std::string& /*obstacle*/)
{
    return prismSolid(std::any_cast<const PrismSize&>(parameters));
}

Real prismReach(const std::any& parameters)
{
    const PrismSize& s = std::any_cast<const PrismSize&>(parameters);
    return 0.5 * Vec3(s.width + 2 * std::abs(s.apex), s.height, s.length).norm();
}

void requirePositiveSize(const char* field, Real value)
{
    if (!(value > 0) || !std::isfinite(value))
    {
        throw InputError(field, "must be a positive number of metres (got " + formatNumber(value) + ")");
    }
}
} // namespace

bridge::ObstacleShape prismSolid(const PrismSize& size)
{
    requirePositiveSize("width", size.width);
    requirePositiveSize("height", size.height);
    requirePositiveSize("length", size.length);
    if (!std::isfinite(size.apex))
    {
        throw InputError("apex", "must be a finite number of metres");
    }
    const Real w = size.width / 2;
    const Real h = size.height / 2;
    const Real l = size.length / 2;
    const Vec3 triangle[3] = {Vec3(-w, -h, 0), Vec3(w, -h, 0), Vec3(size.apex, h, 0)};
    bridge::ObstacleShape solid;
    solid.kind = bridge::SolidKind::Polyhedron;
    for (Real z : {l, -l})
    {
        for (const Vec3& corner : triangle)
        {
            solid.polygons.vertices.push_back(corner + Vec3(0, 0, z));
        }
    }
    solid.polygons.faces = {
        {0, 1, 4, 3}, // base
        {1, 2, 5, 4}, // +x side
        {2, 0, 3, 5}, // -x side
        {0, 1, 2},    // +z end
        {3, 4, 5},    // -z end
    };
    return solid;
}

extern const ShapeEntry prismShape = {
    .name = "prism",
    .closed = true,
    .read = readPrism,
    .solid = prismSolidOf,
    .reach = prismReach,
};
} // namespace masse::scene
