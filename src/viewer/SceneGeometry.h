#pragma once
/// What the window draws, as plain arrays: the GL-free half of the renderer. From a snapshot it makes the sheet's
/// per-mass positions, colours and normals (drawn through the topology's fixed index buffers), the room, obstacles
/// and heaters as triangles and lines, and the overlays (pick spring, scripted grabs, Bullet's ghost). The Renderer
/// only uploads these arrays and draws them; the tests read them without a GL context.

#include "MassScalars.h"
#include "Palette.h"
#include "SceneSnapshot.h"

#include "core/lattice/Lattice.h"

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace masse::viewer
{
enum class DrawMode
{
    MassesAndSprings, ///< the paper's look
    Surface,          ///< the sheet as one lit closed surface, red and green as the masses
    Scalar,           ///< the surface coloured by a registered per-mass scalar
};

/// Parses "masses", "surface" or "scalar"; throws InputError naming the allowed names.
DrawMode parseDrawMode(std::string_view name);
std::string_view drawModeName(DrawMode mode);

struct DrawSettings
{
    DrawMode mode = DrawMode::MassesAndSprings;
    std::string scalar = "speed"; ///< a name in the scalar registry (Scalar mode)
    bool showRoom = true;
    bool operator==(const DrawSettings&) const = default;
};

/// The sheet drawn as one closed surface, three mass indices per triangle: the bottom of the bottom layer (facing
/// down), the top of the top layer (facing up), and the sides closed by strips between the boundary rings of each
/// pair of neighbouring layers, all wound outward. The inner layers' faces are left out: they are hidden inside, and
/// a two-layer sheet reads as one sheet of its real thickness rather than two surfaces a layer spacing apart. A
/// one-layer sheet is its single surface.
std::vector<std::uint32_t> sheetSurfaceTriangles(const Lattice& lattice);

/// The same closed surface over the masses of every `stride`-th row and column (and the last ones, so the sheet keeps
/// its extent), for a sheet whose masses lie under a couple of pixels apart on screen: the bottom and top layers as
/// coarse grids, the sides zipped from the bottom layer's rim to the top layer's. stride 1 is sheetSurfaceTriangles.
std::vector<std::uint32_t> coarseSurfaceTriangles(const Lattice& lattice, int stride);

/// The masses on every `stride`-th row and column of each layer (row and column multiples of the stride), in mass
/// order: a sheet drawn with these reads the same as with all of its masses once they are under a couple of pixels
/// apart on screen, at a fraction of the cost (Mesa's software rasteriser turns each point into a quad on the
/// drawing thread).
std::vector<std::uint32_t> massesAtStride(const Lattice& lattice, int stride);

/// The coarsest stride kept, and the on-screen spacing (px) masses mode keeps between the masses it draws.
inline constexpr int maxMassStride = 16;
inline constexpr Real minMassSpacingPixels = 2.5;

/// The power of two (1 .. maxMassStride) by which to thin masses `spacingPixels` apart on screen so the ones drawn
/// are at least minMassSpacingPixels apart.
int massStride(Real spacingPixels);

/// One vertex of the room, obstacles, heaters and overlays: position, colour, normal (zero for lines and points).
struct GeometryVertex
{
    float position[3];
    float colour[3];
    float normal[3];
};

/// The sheet's per-mass arrays, three floats a mass, in mass order (the topology's indices point into them).
struct SheetArrays
{
    std::vector<float> positions;
    std::vector<float> colours;
    std::vector<float> normals; ///< only in the surface modes (empty for masses and springs)
    Vec3 centre = Vec3::Zero(); ///< mean position (sizes the mass points by their depth)
    /// The range the colours map (Scalar mode with values); nothing when the sheet is not coloured by a scalar.
    std::optional<ScalarRange> scalarRange;
};

/// Fills `out` (reusing its storage) from the snapshot: scalar colours through viridis over the values' range, grey
/// when the scene lacks the scalar, otherwise the paper's colours (red, green in contact, blue pinned).
void buildSheetArrays(const SceneSnapshot& snapshot, const DrawSettings& settings, SheetArrays& out);

/// Area-weighted vertex normals over the triangles (three floats a mass, not normalised).
void vertexNormals(const std::vector<Vec3>& positions, const std::vector<std::uint32_t>& triangles,
                   std::vector<float>& out);

/// The room, the polyhedra and the heat sources.
struct EnvironmentGeometry
{
    std::vector<GeometryVertex> roomFaces;  ///< the inner face of each room box (drawn with back faces culled)
    std::vector<GeometryVertex> solidFaces; ///< polyhedra, two-sided
    /// Edges, the floor grid, heaters (outline, elements, rays), hot-air zone boxes.
    std::vector<GeometryVertex> lines;
};
EnvironmentGeometry buildEnvironment(const SceneSnapshot& snapshot, bool showRoom);

/// A heater's elements glow this colour when on and are dark when off.
Rgb heaterColour(bool on);

/// The overlays, drawn over everything.
struct OverlayGeometry
{
    std::vector<GeometryVertex> lines;
    std::vector<GeometryVertex> points;
};
/// `pick`: the window's own pick (mass, target), fresher than the snapshot's; the snapshot's is drawn without it.
OverlayGeometry buildOverlays(const SceneSnapshot& snapshot, const std::optional<std::pair<Index, Vec3>>& pick);

/// A coil from `from` to `to` as a polyline (first point `from`, last `to`): `turns` turns of radius `radius` about
/// the line between them, so the pick spring reads as a spring, stretched as far as it is pulled.
std::vector<Vec3> springCoil(const Vec3& from, const Vec3& to, Real radius, int turns);
} // namespace masse::viewer
