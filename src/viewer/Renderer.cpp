#include "Renderer.h"

#include "Palette.h"
#include "ScreenRegions.h"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstddef>
#include <limits>

namespace masse::viewer
{
namespace
{
constexpr GLuint positionAttribute = 0;
constexpr GLuint colourAttribute = 1;
constexpr GLuint normalAttribute = 2;

constexpr const char* flatVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 colour;
uniform mat4 viewProjection;
uniform float pointSize;
out vec3 vertexColour;
void main()
{
    gl_Position = viewProjection * vec4(position, 1.0);
    gl_PointSize = pointSize;
    vertexColour = colour;
}
)";

constexpr const char* flatFragmentShader = R"(#version 330 core
in vec3 vertexColour;
uniform bool roundPoints;
out vec4 fragmentColour;
void main()
{
    if (roundPoints && length(gl_PointCoord - vec2(0.5)) > 0.5)
        discard;
    fragmentColour = vec4(vertexColour, 1.0);
}
)";

constexpr const char* litVertexShader = R"(#version 330 core
layout(location = 0) in vec3 position;
layout(location = 1) in vec3 colour;
layout(location = 2) in vec3 normal;
uniform mat4 viewProjection;
out vec3 vertexColour;
out vec3 vertexNormal;
void main()
{
    gl_Position = viewProjection * vec4(position, 1.0);
    vertexColour = colour;
    vertexNormal = normal;
}
)";

// Two-sided: the sheet is seen from above and below (the paper's figure 8). The ambient term keeps every lit colour
// well away from black, which is reserved for touched faces.
constexpr const char* litFragmentShader = R"(#version 330 core
in vec3 vertexColour;
in vec3 vertexNormal;
uniform vec3 lightDirection;
uniform float ambient;
out vec4 fragmentColour;
void main()
{
    float diffuse = abs(dot(normalize(vertexNormal), lightDirection));
    fragmentColour = vec4(vertexColour * (ambient + (1.0 - ambient) * diffuse), 1.0);
}
)";

constexpr float ambientLight = 0.45f;
constexpr Real minSpringSpacingPixels = 3;

void setMatrix(const ShaderProgram& program, const char* name, const Mat4& matrix)
{
    const Eigen::Matrix4f m = matrix.cast<float>();
    glUniformMatrix4fv(program.uniform(name), 1, GL_FALSE, m.data());
}

} // namespace

Renderer::Renderer()
    : m_flat(std::make_unique<ShaderProgram>(flatVertexShader, flatFragmentShader)),
      m_lit(std::make_unique<ShaderProgram>(litVertexShader, litFragmentShader))
{
    glGenVertexArrays(1, &m_sheetVao);
    glGenBuffers(1, &m_positions);
    glGenBuffers(1, &m_colours);
    glGenBuffers(1, &m_normals);
    glGenBuffers(1, &m_springIndices);
    glGenBuffers(1, &m_surfaceIndices);
    glBindVertexArray(m_sheetVao);
    const std::pair<GLuint, GLuint> arrays[] = {
        {m_positions, positionAttribute}, {m_colours, colourAttribute}, {m_normals, normalAttribute}};
    for (const auto& [buffer, attribute] : arrays)
    {
        glBindBuffer(GL_ARRAY_BUFFER, buffer);
        glVertexAttribPointer(attribute, 3, GL_FLOAT, GL_FALSE, 0, nullptr);
        glEnableVertexAttribArray(attribute);
    }

    for (VertexStream* stream : {&m_roomFaces, &m_solidFaces, &m_lines, &m_overlayLines, &m_overlayPoints})
    {
        glGenVertexArrays(1, &stream->vao);
        glGenBuffers(1, &stream->vbo);
        glBindVertexArray(stream->vao);
        glBindBuffer(GL_ARRAY_BUFFER, stream->vbo);
        glVertexAttribPointer(positionAttribute, 3, GL_FLOAT, GL_FALSE, sizeof(GeometryVertex),
                              reinterpret_cast<const void*>(offsetof(GeometryVertex, position)));
        glVertexAttribPointer(colourAttribute, 3, GL_FLOAT, GL_FALSE, sizeof(GeometryVertex),
                              reinterpret_cast<const void*>(offsetof(GeometryVertex, colour)));
        glVertexAttribPointer(normalAttribute, 3, GL_FLOAT, GL_FALSE, sizeof(GeometryVertex),
                              reinterpret_cast<const void*>(offsetof(GeometryVertex, normal)));
        glEnableVertexAttribArray(positionAttribute);
        glEnableVertexAttribArray(colourAttribute);
        glEnableVertexAttribArray(normalAttribute);
    }
    glBindVertexArray(0);
}

Renderer::~Renderer()
{
    for (VertexStream* stream : {&m_roomFaces, &m_solidFaces, &m_lines, &m_overlayLines, &m_overlayPoints})
    {
        glDeleteBuffers(1, &stream->vbo);
        glDeleteVertexArrays(1, &stream->vao);
    }
    const GLuint buffers[] = {m_positions, m_colours, m_normals, m_springIndices, m_surfaceIndices};
    glDeleteBuffers(5, buffers);
    glDeleteBuffers(GLsizei(m_coarseMassIndices.size()), m_coarseMassIndices.data());
    glDeleteBuffers(GLsizei(m_coarseSurfaceIndices.size()), m_coarseSurfaceIndices.data());
    glDeleteVertexArrays(1, &m_sheetVao);
}

void Renderer::rebuildTopology(const SheetTopology& topology)
{
    const std::vector<std::uint32_t>& springIndices = topology.springIndices;
    const std::vector<std::uint32_t>& surfaceTriangles = topology.surfaceTriangles;
    glBindVertexArray(0);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m_springIndices);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(springIndices.size() * sizeof(std::uint32_t)),
                 springIndices.data(), GL_STATIC_DRAW);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m_surfaceIndices);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(surfaceTriangles.size() * sizeof(std::uint32_t)),
                 surfaceTriangles.data(), GL_STATIC_DRAW);
    auto fillLevels = [](const std::vector<std::vector<std::uint32_t>>& levels, std::vector<GLuint>& buffers,
                         std::vector<GLsizei>& counts)
    {
        glDeleteBuffers(GLsizei(buffers.size()), buffers.data());
        buffers.assign(levels.size(), 0);
        counts.clear();
        glGenBuffers(GLsizei(buffers.size()), buffers.data());
        for (std::size_t k = 0; k < levels.size(); ++k)
        {
            glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, buffers[k]);
            glBufferData(GL_ELEMENT_ARRAY_BUFFER, GLsizeiptr(levels[k].size() * sizeof(std::uint32_t)),
                         levels[k].data(), GL_STATIC_DRAW);
            counts.push_back(GLsizei(levels[k].size()));
        }
    };
    fillLevels(topology.coarseMasses, m_coarseMassIndices, m_coarseMassCounts);
    fillLevels(topology.coarseSurfaces, m_coarseSurfaceIndices, m_coarseSurfaceCounts);
    m_springIndexCount = GLsizei(springIndices.size());
    m_surfaceIndexCount = GLsizei(surfaceTriangles.size());
    m_spacing = topology.spacing;
}

namespace
{
/// Refills a buffer in place when its size is unchanged (a new snapshot of the same sheet): no new storage for the
/// driver to allocate and fault in at every upload.
void fillBuffer(GLuint buffer, const std::vector<float>& data, GLsizeiptr& allocated)
{
    const GLsizeiptr bytes = GLsizeiptr(data.size() * sizeof(float));
    glBindBuffer(GL_ARRAY_BUFFER, buffer);
    if (bytes == allocated)
    {
        glBufferSubData(GL_ARRAY_BUFFER, 0, bytes, data.data());
    }
    else
    {
        glBufferData(GL_ARRAY_BUFFER, bytes, data.data(), GL_DYNAMIC_DRAW);
        allocated = bytes;
    }
}
} // namespace

void Renderer::uploadSheet()
{
    fillBuffer(m_positions, m_sheet.positions, m_allocated[0]);
    fillBuffer(m_colours, m_sheet.colours, m_allocated[1]);
    if (!m_sheet.normals.empty())
    {
        fillBuffer(m_normals, m_sheet.normals, m_allocated[2]);
    }
}

void Renderer::upload(VertexStream& stream, const std::vector<GeometryVertex>& vertices)
{
    glBindBuffer(GL_ARRAY_BUFFER, stream.vbo);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertices.size() * sizeof(GeometryVertex)), vertices.data(),
                 GL_STREAM_DRAW);
    stream.count = GLsizei(vertices.size());
}

void Renderer::drawSheet(const DrawSettings& settings, const OrbitCamera& camera, const Viewport& viewport)
{
    glBindVertexArray(m_sheetVao);
    const Real depth = std::max((m_sheet.centre - camera.eye()).norm(), camera.nearPlane());
    const Real spacingPixels = m_spacing / (depth * camera.pixelSizeAtUnitDepth(viewport));
    // Masses under a couple of pixels apart are thinned to every 2nd, 4th... row and column, in the surface modes as
    // in masses mode: the sheet reads the same, and drawing 130,000 points (each a quad made on this thread by Mesa's
    // software rasteriser) or 260,000 triangles is most of a 256x2x256 frame.
    m_massStride = viewer::massStride(spacingPixels);
    const std::size_t level = std::size_t(std::countr_zero(unsigned(m_massStride)));
    const bool thinned = level > 0 && level <= m_coarseMassIndices.size() && level <= m_coarseSurfaceIndices.size();
    if (!thinned)
    {
        m_massStride = 1;
    }
    if (settings.mode == DrawMode::MassesAndSprings)
    {
        m_flat->use();
        // Springs closer together on screen than a few pixels only fill the sheet with grey, and they are most of
        // a dense sheet's drawing cost; below that the masses alone show it.
        m_springsShown = spacingPixels >= minSpringSpacingPixels;
        if (m_springsShown)
        {
            // Springs in one colour: the colour array is switched off and its attribute's constant value used.
            glDisableVertexAttribArray(colourAttribute);
            glVertexAttrib3f(colourAttribute, palette::spring.r, palette::spring.g, palette::spring.b);
            glUniform1i(m_flat->uniform("roundPoints"), 0);
            glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m_springIndices);
            glDrawElements(GL_LINES, m_springIndexCount, GL_UNSIGNED_INT, nullptr);
            glEnableVertexAttribArray(colourAttribute);
        }
        // Masses as round points about half the spacing of those drawn across on screen, within readable bounds.
        glUniform1f(m_flat->uniform("pointSize"),
                    float(std::clamp(Real(0.45) * spacingPixels * m_massStride, Real(2), Real(9))));
        glUniform1i(m_flat->uniform("roundPoints"), 1);
        if (thinned)
        {
            glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m_coarseMassIndices[level - 1]);
            glDrawElements(GL_POINTS, m_coarseMassCounts[level - 1], GL_UNSIGNED_INT, nullptr);
        }
        else
        {
            glDrawArrays(GL_POINTS, 0, GLsizei(m_sheet.positions.size() / 3));
        }
    }
    else
    {
        m_lit->use();
        // A sheet of two or more layers is drawn as a closed surface wound outward, so its faces turned away from the
        // camera lie behind its front ones: culled, the rasteriser skips half the sheet (a one-layer sheet is its
        // single surface, seen from both sides).
        const bool closed = m_topology && m_topology->layers >= 2;
        if (closed)
        {
            glEnable(GL_CULL_FACE);
            glCullFace(GL_BACK);
            glFrontFace(GL_CCW);
        }
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, thinned ? m_coarseSurfaceIndices[level - 1] : m_surfaceIndices);
        glDrawElements(GL_TRIANGLES, thinned ? m_coarseSurfaceCounts[level - 1] : m_surfaceIndexCount, GL_UNSIGNED_INT,
                       nullptr);
        glDisable(GL_CULL_FACE);
    }
    glBindVertexArray(0);
}

void Renderer::draw(const SceneSnapshot& snapshot, const std::optional<std::pair<Index, Vec3>>& pick,
                    const OrbitCamera& camera, const Viewport& viewport, const DrawSettings& settings)
{
    if (m_topology != snapshot.topology)
    {
        m_topology = snapshot.topology;
        rebuildTopology(*m_topology);
    }
    if (&snapshot != m_uploadedSnapshot || snapshot.sequence != m_uploadedSequence || m_uploadedSequence == 0 ||
        !(settings == m_uploadedSettings))
    {
        // A new snapshot (or other settings): the sheet's arrays and the environment are made again and uploaded.
        buildSheetArrays(snapshot, settings, m_sheet);
        uploadSheet();
        const EnvironmentGeometry environment = buildEnvironment(snapshot, settings.showRoom);
        upload(m_roomFaces, environment.roomFaces);
        upload(m_solidFaces, environment.solidFaces);
        upload(m_lines, environment.lines);
        m_uploadedSnapshot = &snapshot;
        m_uploadedSequence = snapshot.sequence;
        m_uploadedSettings = settings;
    }
    // The overlays follow the mouse: small, made every frame.
    const OverlayGeometry overlays = buildOverlays(snapshot, pick);
    upload(m_overlayLines, overlays.lines);
    upload(m_overlayPoints, overlays.points);

    glViewport(0, 0, viewport.width, viewport.height);
    glClearColor(palette::background.r, palette::background.g, palette::background.b, 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDepthFunc(GL_LEQUAL);
    glEnable(GL_PROGRAM_POINT_SIZE);

    const Mat4 viewProjection = camera.viewProjection(viewport);
    // A light over the viewer's left shoulder, moving with the camera, so no face is ever seen unlit.
    const Vec3 light = (-camera.forward() + Real(0.8) * camera.up() - Real(0.4) * camera.right()).normalized();
    m_lit->use();
    setMatrix(*m_lit, "viewProjection", viewProjection);
    glUniform3f(m_lit->uniform("lightDirection"), float(light.x()), float(light.y()), float(light.z()));
    glUniform1f(m_lit->uniform("ambient"), ambientLight);
    m_flat->use();
    setMatrix(*m_flat, "viewProjection", viewProjection);

    m_lit->use();
    glEnable(GL_CULL_FACE);
    glCullFace(GL_BACK);
    glFrontFace(GL_CCW);
    glBindVertexArray(m_roomFaces.vao);
    glDrawArrays(GL_TRIANGLES, 0, m_roomFaces.count);
    glDisable(GL_CULL_FACE);
    // Polyhedra pushed back a little in depth so their edges and the masses resting on them draw cleanly on top.
    glEnable(GL_POLYGON_OFFSET_FILL);
    glPolygonOffset(1, 1);
    glBindVertexArray(m_solidFaces.vao);
    glDrawArrays(GL_TRIANGLES, 0, m_solidFaces.count);
    glDisable(GL_POLYGON_OFFSET_FILL);

    m_flat->use();
    glUniform1i(m_flat->uniform("roundPoints"), 0);
    glBindVertexArray(m_lines.vao);
    glDrawArrays(GL_LINES, 0, m_lines.count);

    drawSheet(settings, camera, viewport);

    // The pick spring and scripted grabs stay visible through everything.
    glDisable(GL_DEPTH_TEST);
    m_flat->use();
    glUniform1i(m_flat->uniform("roundPoints"), 0);
    glBindVertexArray(m_overlayLines.vao);
    glLineWidth(2);
    glDrawArrays(GL_LINES, 0, m_overlayLines.count);
    glLineWidth(1);
    glUniform1i(m_flat->uniform("roundPoints"), 1);
    glUniform1f(m_flat->uniform("pointSize"), 10);
    glBindVertexArray(m_overlayPoints.vao);
    glDrawArrays(GL_POINTS, 0, m_overlayPoints.count);
    glBindVertexArray(0);
    glEnable(GL_DEPTH_TEST);
}
} // namespace masse::viewer
