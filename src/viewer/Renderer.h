#pragma once
/// Draws a scene with OpenGL 3.3 core: the room, the polyhedra (a face a mass touches turns black), the sheet (masses
/// red, green in contact; or a shaded surface; or a surface coloured by a scalar), and the pick spring.
///
/// The sheet costs a handful of calls per frame whatever its size: its positions go to the GPU once per frame in one
/// buffer, springs are drawn from a fixed index buffer in one call, the masses in another, each surface in one more.

#include "Camera.h"
#include "MassScalars.h"
#include "SceneSnapshot.h"
#include "ShaderProgram.h"

#include <memory>
#include <optional>
#include <utility>
#include <string>
#include <string_view>
#include <vector>

namespace masse::viewer
{
enum class DrawMode
{
    MassesAndSprings, ///< the paper's look
    Surface,          ///< the top and bottom layers as lit surfaces, red and green as the masses
    Scalar,           ///< the surfaces coloured by a registered per-mass scalar
};

/// Parses "masses", "surface" or "scalar"; throws InputError naming the allowed names.
DrawMode parseDrawMode(std::string_view name);
std::string_view drawModeName(DrawMode mode);

struct DrawSettings
{
    DrawMode mode = DrawMode::MassesAndSprings;
    std::string scalar = "speed"; ///< a name in the scalar registry (Scalar mode)
    bool showRoom = true;
};

class Renderer
{
public:
    /// Needs a current OpenGL 3.3 core context; throws std::runtime_error if a shader does not build.
    Renderer();
    ~Renderer();
    Renderer(const Renderer&) = delete;
    Renderer& operator=(const Renderer&) = delete;

    /// Draws a snapshot. `pick`: the window's own pick (mass, target), fresher than the snapshot's: the pick spring
    /// shows in the frame after the click whatever the simulation is doing.
    void draw(const SceneSnapshot& snapshot, const std::optional<std::pair<Index, Vec3>>& pick,
              const OrbitCamera& camera, const Viewport& viewport, const DrawSettings& settings);

    /// The range the last Scalar frame mapped onto the colour map (for the panel's legend).
    const ScalarRange& scalarRange() const { return m_scalarRange; }
    /// Whether the last frame drew the springs (in masses mode they are left out while they lie closer together
    /// on screen than a few pixels).
    bool springsShown() const { return m_springsShown; }

private:
    /// One vertex of the room, the obstacles and the overlays: position, colour, normal (zero for lines).
    struct Vertex
    {
        float position[3];
        float colour[3];
        float normal[3];
    };
    /// A vertex array over one interleaved buffer of Vertex, refilled as needed.
    struct VertexStream
    {
        GLuint vao = 0;
        GLuint vbo = 0;
        GLsizei count = 0;
    };

    void rebuildTopology(const SheetTopology& topology);
    void uploadSheet(const SceneSnapshot& snapshot, const DrawSettings& settings);
    void buildEnvironment(const SceneSnapshot& snapshot, bool showRoom);
    void buildOverlays(const SceneSnapshot& snapshot, const std::optional<std::pair<Index, Vec3>>& pick);
    void upload(VertexStream& stream, const std::vector<Vertex>& vertices);
    void drawSheet(const DrawSettings& settings, const OrbitCamera& camera, const Viewport& viewport);

    std::unique_ptr<ShaderProgram> m_flat; ///< unlit colours; points round
    std::unique_ptr<ShaderProgram> m_lit;  ///< two-sided diffuse and ambient

    // The sheet: per-mass buffers refilled each frame, index buffers rebuilt with the scene.
    GLuint m_sheetVao = 0;
    GLuint m_positions = 0;
    GLuint m_colours = 0;
    GLuint m_normals = 0;
    GLuint m_springIndices = 0;
    GLuint m_surfaceIndices = 0;
    GLsizei m_springIndexCount = 0;
    GLsizei m_surfaceIndexCount = 0;
    std::shared_ptr<const SheetTopology> m_topology;
    Real m_spacing = 0; ///< m, the lattice's smallest spacing (sizes the mass points)

    // Per-frame scratch, kept to avoid reallocating.
    std::vector<float> m_positionData;
    std::vector<float> m_colourData;
    std::vector<float> m_normalData;
    std::vector<float> m_scalarValues;
    Vec3 m_sheetCentre = Vec3::Zero();
    ScalarRange m_scalarRange;
    bool m_springsShown = true;

    VertexStream m_roomFaces;  ///< inward faces of the room, drawn with back faces culled
    VertexStream m_solidFaces; ///< polyhedra
    VertexStream m_lines;      ///< obstacle edges, floor grid
    VertexStream m_overlayLines;
    VertexStream m_overlayPoints;
    std::vector<Vertex> m_scratch;
};
} // namespace masse::viewer
