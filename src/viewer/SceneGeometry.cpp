#include "SceneGeometry.h"

#include "core/InputError.h"
#include "core/lattice/LatticeSurface.h"
#include "core/material/HeatSources.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace masse::viewer
{
namespace
{
constexpr Real pi = Real(3.14159265358979323846);
/// Heating elements drawn across a heater panel.
constexpr int heaterElements = 7;

void put(float* out, const Vec3& v)
{
    out[0] = float(v.x());
    out[1] = float(v.y());
    out[2] = float(v.z());
}

void put(float* out, const Rgb& c)
{
    out[0] = c.r;
    out[1] = c.g;
    out[2] = c.b;
}

GeometryVertex vertex(const Vec3& position, const Rgb& colour, const Vec3& normal = Vec3::Zero())
{
    GeometryVertex v{};
    put(v.position, position);
    put(v.colour, colour);
    put(v.normal, normal);
    return v;
}

void addLine(std::vector<GeometryVertex>& out, const Vec3& a, const Vec3& b, const Rgb& colour)
{
    out.push_back(vertex(a, colour));
    out.push_back(vertex(b, colour));
}

/// Appends a polygon as a fan of triangles (its winding kept), all with the face's normal and colour.
void appendPolygon(std::vector<GeometryVertex>& out, const std::vector<Vec3>& corners, const Vec3& normal,
                   const Rgb& colour)
{
    for (std::size_t k = 1; k + 1 < corners.size(); ++k)
    {
        for (const Vec3* p : {&corners[0], &corners[k], &corners[k + 1]})
        {
            out.push_back(vertex(*p, colour, normal));
        }
    }
}

} // namespace

DrawMode parseDrawMode(std::string_view name)
{
    if (name == "masses")
    {
        return DrawMode::MassesAndSprings;
    }
    if (name == "surface")
    {
        return DrawMode::Surface;
    }
    if (name == "scalar")
    {
        return DrawMode::Scalar;
    }
    throw InputError("draw: unknown mode '" + std::string(name) + "' (expected masses, surface, scalar)");
}

std::string_view drawModeName(DrawMode mode)
{
    switch (mode)
    {
    case DrawMode::MassesAndSprings:
        return "masses";
    case DrawMode::Surface:
        return "surface";
    case DrawMode::Scalar:
        return "scalar";
    }
    return "masses";
}

std::vector<std::uint32_t> sheetSurfaceTriangles(const Lattice& lattice)
{
    std::vector<std::uint32_t> out;
    auto add = [&out](Index a, Index b, Index c)
    {
        out.push_back(std::uint32_t(a));
        out.push_back(std::uint32_t(b));
        out.push_back(std::uint32_t(c));
    };
    const int layers = lattice.spec.layers;
    // layerTriangles face up at rest: the top keeps its winding, the bottom is turned over to face down.
    for (const Triangle& t : layerTriangles(lattice, 0))
    {
        if (layers > 1)
        {
            add(t[0], t[2], t[1]);
        }
        else
        {
            add(t[0], t[1], t[2]);
        }
    }
    if (layers == 1)
    {
        return out;
    }
    for (const Triangle& t : layerTriangles(lattice, layers - 1))
    {
        add(t[0], t[1], t[2]);
    }

    // The sides (rimStrips), each wound to face out.
    Vec3 centre = Vec3::Zero();
    for (const Vec3& p : lattice.position)
    {
        centre += p;
    }
    centre /= Real(std::max<std::size_t>(1, lattice.position.size()));
    auto addOutward = [&](Index a, Index b, Index c)
    {
        // Wound so the normal points away from the sheet's middle, horizontally (the sides at rest face out).
        const Vec3& pa = lattice.position[a];
        const Vec3 normal = (lattice.position[b] - pa).cross(lattice.position[c] - pa);
        Vec3 outward = (pa + lattice.position[b] + lattice.position[c]) / 3 - centre;
        outward.y() = 0;
        if (normal.dot(outward) < 0)
        {
            add(a, c, b);
        }
        else
        {
            add(a, b, c);
        }
    };
    for (const std::vector<Triangle>& strip : rimStrips(lattice))
    {
        for (const Triangle& t : strip)
        {
            addOutward(t[0], t[1], t[2]);
        }
    }
    return out;
}

namespace
{
/// 0, stride, 2 stride ... and the last of count.
std::vector<int> strideLines(int count, int stride)
{
    std::vector<int> lines;
    for (int k = 0; k < count; k += stride)
    {
        lines.push_back(k);
    }
    if (lines.back() != count - 1)
    {
        lines.push_back(count - 1);
    }
    return lines;
}

/// A layer's rim at the stride: its four sides, each from corner to corner.
std::array<std::vector<Index>, 4> coarseSides(const Lattice& lattice, int layer, int stride)
{
    const int nx = lattice.layerCountX(layer);
    const int nz = lattice.layerCountZ(layer);
    const std::vector<int> columns = strideLines(nx, stride);
    const std::vector<int> rows = strideLines(nz, stride);
    std::array<std::vector<Index>, 4> sides;
    for (std::size_t k = 0; k < columns.size(); ++k)
    {
        sides[0].push_back(lattice.index(layer, 0, columns[k]));
        sides[2].push_back(lattice.index(layer, nz - 1, columns[columns.size() - 1 - k]));
    }
    for (std::size_t k = 0; k < rows.size(); ++k)
    {
        sides[1].push_back(lattice.index(layer, rows[k], nx - 1));
        sides[3].push_back(lattice.index(layer, rows[rows.size() - 1 - k], 0));
    }
    return sides;
}
} // namespace

std::vector<std::uint32_t> coarseSurfaceTriangles(const Lattice& lattice, int stride)
{
    if (stride <= 1)
    {
        return sheetSurfaceTriangles(lattice);
    }
    std::vector<std::uint32_t> out;
    const int layers = lattice.spec.layers;
    Vec3 centre = Vec3::Zero();
    for (const Vec3& p : lattice.position)
    {
        centre += p;
    }
    centre /= Real(std::max<std::size_t>(1, lattice.position.size()));
    // Wound so the normal points along `outward` at rest.
    auto addFacing = [&](Index a, Index b, Index c, const Vec3& outward)
    {
        const Vec3& pa = lattice.position[a];
        const Vec3 normal = (lattice.position[b] - pa).cross(lattice.position[c] - pa);
        const bool flip = normal.dot(outward) < 0;
        out.push_back(std::uint32_t(a));
        out.push_back(std::uint32_t(flip ? c : b));
        out.push_back(std::uint32_t(flip ? b : c));
    };
    std::vector<int> surfaceLayers{0};
    if (layers > 1)
    {
        surfaceLayers.push_back(layers - 1);
    }
    for (int layer : surfaceLayers)
    {
        const Vec3 facing = layers > 1 && layer == 0 ? Vec3(0, -1, 0) : Vec3(0, 1, 0);
        const std::vector<int> columns = strideLines(lattice.layerCountX(layer), stride);
        const std::vector<int> rows = strideLines(lattice.layerCountZ(layer), stride);
        for (std::size_t r = 0; r + 1 < rows.size(); ++r)
        {
            for (std::size_t c = 0; c + 1 < columns.size(); ++c)
            {
                const Index a = lattice.index(layer, rows[r], columns[c]);
                const Index b = lattice.index(layer, rows[r], columns[c + 1]);
                const Index d = lattice.index(layer, rows[r + 1], columns[c]);
                const Index e = lattice.index(layer, rows[r + 1], columns[c + 1]);
                addFacing(a, b, e, facing);
                addFacing(a, e, d, facing);
            }
        }
    }
    if (layers == 1)
    {
        return out;
    }
    // Sides: each side of the bottom rim zipped to the same side of the top rim, advancing along whichever is behind
    // (by its fraction of the way along the side); corners are shared by neighbouring sides, so the strips close.
    const auto lower = coarseSides(lattice, 0, stride);
    const auto upper = coarseSides(lattice, layers - 1, stride);
    for (std::size_t side = 0; side < 4; ++side)
    {
        const std::vector<Index>& b = lower[side];
        const std::vector<Index>& t = upper[side];
        std::size_t i = 0;
        std::size_t j = 0;
        while (i + 1 < b.size() || j + 1 < t.size())
        {
            const Real nextB = i + 1 < b.size() ? Real(i + 1) / Real(b.size() - 1) : Real(2);
            const Real nextT = j + 1 < t.size() ? Real(j + 1) / Real(t.size() - 1) : Real(2);
            Index a = b[i];
            Index c = t[j];
            Index next = 0;
            if (nextB <= nextT)
            {
                next = b[++i];
            }
            else
            {
                next = t[++j];
            }
            Vec3 outward = (lattice.position[a] + lattice.position[c] + lattice.position[next]) / 3 - centre;
            outward.y() = 0;
            addFacing(a, next, c, outward);
        }
    }
    return out;
}

std::vector<std::uint32_t> massesAtStride(const Lattice& lattice, int stride)
{
    std::vector<std::uint32_t> out;
    for (std::size_t i = 0; i < lattice.coord.size(); ++i)
    {
        const LatticeCoord& c = lattice.coord[i];
        if (c.row % stride == 0 && c.column % stride == 0)
        {
            out.push_back(std::uint32_t(i));
        }
    }
    return out;
}

int massStride(Real spacingPixels)
{
    int stride = 1;
    while (stride < maxMassStride && spacingPixels * stride < minMassSpacingPixels)
    {
        stride *= 2;
    }
    return stride;
}

void vertexNormals(const std::vector<Vec3>& positions, const std::vector<std::uint32_t>& triangles,
                   std::vector<float>& out)
{
    out.assign(3 * positions.size(), 0.0f);
    for (std::size_t t = 0; t + 2 < triangles.size(); t += 3)
    {
        const std::uint32_t a = triangles[t];
        const std::uint32_t b = triangles[t + 1];
        const std::uint32_t c = triangles[t + 2];
        const Vec3 normal = (positions[b] - positions[a]).cross(positions[c] - positions[a]);
        for (std::uint32_t k : {a, b, c})
        {
            out[3 * k] += float(normal.x());
            out[3 * k + 1] += float(normal.y());
            out[3 * k + 2] += float(normal.z());
        }
    }
}

void buildSheetArrays(const SceneSnapshot& snapshot, const DrawSettings& settings, SheetArrays& out)
{
    const std::vector<Vec3>& positions = snapshot.positions;
    const std::size_t n = positions.size();
    out.positions.resize(3 * n);
    out.colours.resize(3 * n);
    Vec3 sum = Vec3::Zero();
    for (std::size_t i = 0; i < n; ++i)
    {
        put(&out.positions[3 * i], positions[i]);
        sum += positions[i];
    }
    out.centre = n > 0 ? Vec3(sum / Real(n)) : Vec3::Zero();

    out.scalarRange.reset();
    const bool scalarMode = settings.mode == DrawMode::Scalar;
    if (scalarMode && snapshot.scalarName == settings.scalar && snapshot.scalar.size() == n && n > 0)
    {
        const ScalarRange range = snapshot.scalarFixedRange.value_or(rangeOf(snapshot.scalar));
        out.scalarRange = range;
        for (std::size_t i = 0; i < n; ++i)
        {
            put(&out.colours[3 * i], viridis(range.normalise(snapshot.scalar[i])));
        }
    }
    else if (scalarMode)
    {
        // A scalar the scene lacks (or not yet evaluated): plain grey, never a colour that reads as data.
        for (std::size_t i = 0; i < n; ++i)
        {
            put(&out.colours[3 * i], palette::missingScalar);
        }
    }
    else
    {
        for (std::size_t i = 0; i < n; ++i)
        {
            const std::uint8_t flag = i < snapshot.flags.size() ? snapshot.flags[i] : std::uint8_t(massFree);
            const Rgb& colour = flag == massPinned          ? palette::pinnedMass
                                : flag == massInSelfContact ? palette::massInSelfContact
                                : flag == massInContact     ? palette::massInContact
                                                            : palette::mass;
            put(&out.colours[3 * i], colour);
        }
    }

    if (settings.mode == DrawMode::MassesAndSprings || !snapshot.topology)
    {
        out.normals.clear();
        return;
    }
    vertexNormals(positions, snapshot.topology->surfaceTriangles, out.normals);
}

Rgb heaterColour(bool on)
{
    return on ? palette::heaterOn : palette::heaterOff;
}

EnvironmentGeometry buildEnvironment(const SceneSnapshot& snapshot, bool showRoom)
{
    EnvironmentGeometry out;
    const scene::RoomSpec& room = snapshot.spec->environment.room;
    const Vec3 roomCentre = (room.minCorner + room.maxCorner) / 2;
    std::vector<Vec3> corners;
    int polyhedron = 0;
    for (const ObstacleShape& obstacle : snapshot.obstacles)
    {
        const std::vector<Vec3>& vertices = obstacle.vertices;
        const auto& faces = obstacle.faces;
        if (obstacle.partOfRoom)
        {
            if (!showRoom)
            {
                continue;
            }
            // A room box lies outside the room; of its faces only the one facing the room's centre is drawn, so
            // the room reads as walls seen from inside, and a wall between the eye and the scene is culled away.
            const Vec3 towardRoom = roomCentre - obstacle.position;
            std::size_t inner = 0;
            Real best = -std::numeric_limits<Real>::infinity();
            for (std::size_t f = 0; f < faces.size(); ++f)
            {
                const Real facing = obstacle.normals[f].dot(towardRoom);
                if (facing > best)
                {
                    best = facing;
                    inner = f;
                }
            }
            corners.clear();
            for (int v : faces[inner])
            {
                corners.push_back(vertices[std::size_t(v)]);
            }
            const Rgb& colour = obstacle.name == "floor" ? palette::floor : palette::wall;
            appendPolygon(out.roomFaces, corners, obstacle.normals[inner], colour);
            continue;
        }
        const Rgb& base = palette::obstacles[std::size_t(polyhedron++) % palette::obstacles.size()];
        for (std::size_t f = 0; f < faces.size(); ++f)
        {
            corners.clear();
            for (int v : faces[f])
            {
                corners.push_back(vertices[std::size_t(v)]);
            }
            appendPolygon(out.solidFaces, corners, obstacle.normals[f],
                          obstacle.touched[f] ? palette::touchedFace : base);
            for (std::size_t k = 0; k < corners.size(); ++k)
            {
                addLine(out.lines, corners[k], corners[(k + 1) % corners.size()], palette::edge);
            }
        }
    }
    if (showRoom && room.enabled)
    {
        // A one-metre grid on the floor, lifted a hair above it so it does not fight the floor for depth.
        const Real y = room.minCorner.y() + Real(0.002);
        for (Real x = std::ceil(room.minCorner.x()); x <= room.maxCorner.x(); x += 1)
        {
            addLine(out.lines, Vec3(x, y, room.minCorner.z()), Vec3(x, y, room.maxCorner.z()), palette::floorGrid);
        }
        for (Real z = std::ceil(room.minCorner.z()); z <= room.maxCorner.z(); z += 1)
        {
            addLine(out.lines, Vec3(room.minCorner.x(), y, z), Vec3(room.maxCorner.x(), y, z), palette::floorGrid);
        }
    }

    // Heat sources: each radiant heater as its panel's outline crossed by heating elements (glowing when on, dark
    // when off), lines rather than a filled face so the sheet under it stays in sight, with short rays from its face
    // in the direction it radiates while on; each hot-air zone as the outline of its box.
    const scene::HeatSpec& heat = snapshot.spec->heat;
    if (!heat.enabled)
    {
        return out;
    }
    const std::vector<RadiantHeater>& heaters = heat.settings.heaters;
    for (std::size_t h = 0; h < heaters.size(); ++h)
    {
        const RadiantHeater& heater = heaters[h];
        const bool on = snapshot.heat && h < snapshot.heat->heatersOn.size()
                            ? bool(snapshot.heat->heatersOn[h])
                            : (h < heat.heaterOn.size() && heat.heaterOn[h]);
        const Rgb colour = heaterColour(on);
        const std::array<Vec3, 4> panel = heaterCorners(heater);
        for (std::size_t k = 0; k < panel.size(); ++k)
        {
            addLine(out.lines, panel[k], panel[(k + 1) % panel.size()], palette::heaterOutline);
        }
        // Elements from the edge panel[0]-panel[1] to the opposite one panel[3]-panel[2].
        for (int element = 1; element <= heaterElements; ++element)
        {
            const Real f = Real(element) / Real(heaterElements + 1);
            addLine(out.lines, panel[0] + f * (panel[1] - panel[0]), panel[3] + f * (panel[2] - panel[3]), colour);
        }
        if (on)
        {
            // Rays a fifth of the panel's smaller side long from its centre and toward its corners.
            const Vec3 normal = heater.normal.normalized();
            const Real reach = Real(0.2) * std::min(heater.width, heater.length);
            addLine(out.lines, heater.centre, heater.centre + reach * normal, colour);
            for (const Vec3& corner : panel)
            {
                const Vec3 from = heater.centre + Real(0.7) * (corner - heater.centre);
                addLine(out.lines, from, from + reach * normal, colour);
            }
        }
    }
    for (const HotAirZone& zone : heat.settings.hotAirZones)
    {
        const Vec3& a = zone.minCorner;
        const Vec3& b = zone.maxCorner;
        for (int axis = 0; axis < 3; ++axis)
        {
            // The four edges along this axis.
            const int u = (axis + 1) % 3;
            const int v = (axis + 2) % 3;
            for (int corner = 0; corner < 4; ++corner)
            {
                Vec3 from = a;
                from[u] = (corner & 1) ? b[u] : a[u];
                from[v] = (corner & 2) ? b[v] : a[v];
                Vec3 to = from;
                to[axis] = b[axis];
                addLine(out.lines, from, to, palette::hotAirZone);
            }
        }
    }
    return out;
}

std::vector<Vec3> springCoil(const Vec3& from, const Vec3& to, Real radius, int turns)
{
    const Vec3 axis = to - from;
    const Real length = axis.norm();
    if (length <= 0 || turns <= 0)
    {
        return {from, to};
    }
    const Vec3 along = axis / length;
    // Any two unit vectors completing a frame with the axis.
    const Vec3 helper = std::abs(along.y()) < Real(0.9) ? Vec3::UnitY() : Vec3::UnitX();
    const Vec3 side = along.cross(helper).normalized();
    const Vec3 other = along.cross(side);
    // Straight leads of a tenth of the length at each end, the coil between them.
    const int perTurn = 12;
    const int segments = turns * perTurn;
    std::vector<Vec3> points{from};
    const Vec3 coilStart = from + Real(0.1) * axis;
    const Vec3 coilAxis = Real(0.8) * axis;
    for (int s = 0; s <= segments; ++s)
    {
        const Real f = Real(s) / Real(segments);
        const Real angle = 2 * pi * Real(turns) * f;
        // The coil's radius tapers to zero at both ends so it joins the leads.
        const Real r = radius * std::sin(pi * f);
        points.push_back(coilStart + f * coilAxis + r * (std::cos(angle) * side + std::sin(angle) * other));
    }
    points.push_back(to);
    return points;
}

OverlayGeometry buildOverlays(const SceneSnapshot& snapshot, const std::optional<std::pair<Index, Vec3>>& pick)
{
    OverlayGeometry out;
    // The thinnest point of a material sheet: a cross three lattice spacings across, over everything (the HUD's
    // panel gives its value).
    if (snapshot.thinnest && snapshot.thinnest->first < snapshot.positions.size())
    {
        const Vec3& x = snapshot.positions[snapshot.thinnest->first];
        const Real arm = Real(1.5) * (snapshot.topology ? snapshot.topology->spacing : Real(0.01));
        for (int axis = 0; axis < 3; ++axis)
        {
            const Vec3 along = arm * Vec3::Unit(axis);
            addLine(out.lines, x - along, x + along, palette::thinnest);
        }
        out.points.push_back(vertex(x, palette::thinnest));
    }
    // The live section: its masses joined along the sheet, each with a short tick up its thickness.
    for (std::size_t k = 0; k < snapshot.section.size(); ++k)
    {
        const scene::SectionPoint& p = snapshot.section[k];
        if (k + 1 < snapshot.section.size())
        {
            addLine(out.lines, p.position, snapshot.section[k + 1].position, palette::section);
        }
        addLine(out.lines, p.position, p.position + Vec3(0, 4 * p.thickness, 0), palette::section);
    }
    for (const auto& [mass, target] : snapshot.grabs)
    {
        addLine(out.lines, mass, target, palette::scriptedGrab);
        out.points.push_back(vertex(mass, palette::scriptedGrab));
    }
    std::optional<std::pair<Index, Vec3>> shown = pick;
    if (!shown && snapshot.pickedMass)
    {
        shown = std::pair<Index, Vec3>(*snapshot.pickedMass, snapshot.pickTarget);
    }
    if (shown && shown->first < snapshot.positions.size())
    {
        // The pick spring as a coil from the mass to the point under the cursor, a few lattice spacings across.
        const Vec3& x = snapshot.positions[shown->first];
        const Real spacing = snapshot.topology ? snapshot.topology->spacing : Real(0.01);
        const Real length = (shown->second - x).norm();
        const Real radius = std::clamp(Real(0.06) * length, Real(0.2) * spacing, spacing);
        const std::vector<Vec3> coil = springCoil(x, shown->second, radius, 8);
        for (std::size_t k = 0; k + 1 < coil.size(); ++k)
        {
            addLine(out.lines, coil[k], coil[k + 1], palette::pick);
        }
        out.points.push_back(vertex(x, palette::pick));
        out.points.push_back(vertex(shown->second, palette::pick));
    }
    // Bullet's twin (--compare) as a ghost over MaSSE's sheet: its links and nodes, nodes in contact coloured.
    if (snapshot.ghost)
    {
        const GhostShape& ghost = *snapshot.ghost;
        for (std::uint32_t node : ghost.links)
        {
            out.lines.push_back(vertex(ghost.nodes[node], palette::ghost));
        }
        for (std::size_t i = 0; i < ghost.nodes.size(); ++i)
        {
            out.points.push_back(vertex(ghost.nodes[i], ghost.touching[i] ? palette::ghostInContact : palette::ghost));
        }
    }
    return out;
}
} // namespace masse::viewer
