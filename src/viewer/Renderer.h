#pragma once
/// Draws a scene with OpenGL 3.3 core: the room, the polyhedra (a face a mass touches turns black), the heaters, the
/// sheet (masses red, green in contact; or a shaded surface; or a surface coloured by a scalar), and the pick spring.
/// What to draw comes from SceneGeometry (no GL); this file only uploads it and draws it.
///
/// The sheet costs a handful of calls per frame whatever its size: springs are drawn from a fixed index buffer in one
/// call, the masses in another, the surface in one more. Its per-mass arrays are rebuilt and uploaded only when a new
/// snapshot (or other draw settings) arrives, not at every frame: on a large sheet the simulation publishes a few
/// snapshots a second while the window redraws (orbiting, picking) many times more often.

#include "Camera.h"
#include "MassScalars.h"
#include "SceneGeometry.h"
#include "SceneSnapshot.h"
#include "ShaderProgram.h"

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace masse::viewer
{
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
    /// Whether the last frame drew the springs (in masses mode they are left out while they lie closer together
    /// on screen than a few pixels).
    bool springsShown() const { return m_springsShown; }
    /// Every how many rows and columns the last frame drew the sheet's masses or surface (1: all of them).
    int massStride() const { return m_massStride; }

private:
    /// A vertex array over one interleaved buffer of GeometryVertex, refilled as needed.
    struct VertexStream
    {
        GLuint vao = 0;
        GLuint vbo = 0;
        GLsizei count = 0;
    };

    void rebuildTopology(const SheetTopology& topology);
    void uploadSheet();
    void upload(VertexStream& stream, const std::vector<GeometryVertex>& vertices);
    void drawSheet(const DrawSettings& settings, const OrbitCamera& camera, const Viewport& viewport);

    std::unique_ptr<ShaderProgram> m_flat; ///< unlit colours; points round
    std::unique_ptr<ShaderProgram> m_lit;  ///< two-sided diffuse and ambient

    // The sheet: per-mass buffers refilled with each new snapshot, index buffers rebuilt with the scene.
    GLuint m_sheetVao = 0;
    GLuint m_positions = 0;
    GLuint m_colours = 0;
    GLuint m_normals = 0;
    GLuint m_springIndices = 0;
    GLuint m_surfaceIndices = 0;
    std::vector<GLuint> m_coarseMassIndices; ///< one element buffer per stride 2, 4, ... (SheetTopology::coarseMasses)
    std::vector<GLsizei> m_coarseMassCounts;
    std::vector<GLuint> m_coarseSurfaceIndices; ///< SheetTopology::coarseSurfaces
    std::vector<GLsizei> m_coarseSurfaceCounts;
    GLsizeiptr m_allocated[3] = {-1, -1, -1}; ///< bytes of storage of m_positions, m_colours, m_normals
    GLsizei m_springIndexCount = 0;
    GLsizei m_surfaceIndexCount = 0;
    std::shared_ptr<const SheetTopology> m_topology;
    Real m_spacing = 0; ///< m, the lattice's smallest spacing (sizes the mass points)
    SheetArrays m_sheet;
    bool m_springsShown = true;
    int m_massStride = 1;

    // What the uploaded buffers were made from: a frame with the same snapshot and settings uploads nothing.
    const SceneSnapshot* m_uploadedSnapshot = nullptr;
    std::uint64_t m_uploadedSequence = 0;
    DrawSettings m_uploadedSettings;

    VertexStream m_roomFaces;  ///< inward faces of the room, drawn with back faces culled
    VertexStream m_solidFaces; ///< polyhedra, heaters
    VertexStream m_lines;      ///< obstacle edges, floor grid, heater rays
    VertexStream m_overlayLines;
    VertexStream m_overlayPoints;
};
} // namespace masse::viewer
