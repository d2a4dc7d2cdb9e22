#include "Renderer.h"

#include "Palette.h"
#include "ScreenRegions.h"

#include "core/InputError.h"
#include "core/LatticeSurface.h"

#include <algorithm>
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

/// Appends a polygon as a fan of triangles (its winding kept), all with the face's normal and colour.
template <typename VertexType>
void appendPolygon(std::vector<VertexType>& out, const std::vector<Vec3>& corners, const Vec3& normal,
                   const Rgb& colour)
{
    for (std::size_t k = 1; k + 1 < corners.size(); ++k)
    {
        for (const Vec3* p : {&corners[0], &corners[k], &corners[k + 1]})
        {
            VertexType v;
            put(v.position, *p);
            put(v.colour, colour);
            put(v.normal, normal);
            out.push_back(v);
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
        glVertexAttribPointer(positionAttribute, 3, GL_FLOAT, GL_FALSE, sizeof(Vertex),
                              reinterpret_cast<const void*>(offsetof(Vertex, position)));
        glVertexAttribPointer(colourAttribute, 3, GL_FLOAT, GL_FALSE, sizeof(Vertex),
                              reinterpret_cast<const void*>(offsetof(Vertex, colour)));
        glVertexAttribPointer(normalAttribute, 3, GL_FLOAT, GL_FALSE, sizeof(Vertex),
                              reinterpret_cast<const void*>(offsetof(Vertex, normal)));
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
    m_springIndexCount = GLsizei(springIndices.size());
    m_surfaceIndexCount = GLsizei(surfaceTriangles.size());
    m_spacing = topology.spacing;
}

void Renderer::uploadSheet(const SceneSnapshot& snapshot, const DrawSettings& settings)
{
    const std::vector<Vec3>& positions = snapshot.positions;
    const std::size_t n = positions.size();
    m_positionData.resize(3 * n);
    m_colourData.resize(3 * n);
    Vec3 sum = Vec3::Zero();
    for (std::size_t i = 0; i < n; ++i)
    {
        put(&m_positionData[3 * i], positions[i]);
        sum += positions[i];
    }
    m_sheetCentre = n > 0 ? Vec3(sum / Real(n)) : Vec3::Zero();

    const bool scalarMode = settings.mode == DrawMode::Scalar;
    if (scalarMode && snapshot.scalarName == settings.scalar && snapshot.scalar.size() == n && n > 0)
    {
        m_scalarRange = rangeOf(snapshot.scalar);
        for (std::size_t i = 0; i < n; ++i)
        {
            put(&m_colourData[3 * i], viridis(m_scalarRange.normalise(snapshot.scalar[i])));
        }
    }
    else if (scalarMode)
    {
        // A scalar the scene lacks (or not yet evaluated): plain grey rather than a uniform colour that reads as data.
        for (std::size_t i = 0; i < n; ++i)
        {
            put(&m_colourData[3 * i], palette::missingScalar);
        }
    }
    else
    {
        for (std::size_t i = 0; i < n; ++i)
        {
            const std::uint8_t flag = i < snapshot.flags.size() ? snapshot.flags[i] : std::uint8_t(massFree);
            const Rgb& colour = flag == massPinned      ? palette::pinnedMass
                                : flag == massInContact ? palette::massInContact
                                                        : palette::mass;
            put(&m_colourData[3 * i], colour);
        }
    }

    glBindBuffer(GL_ARRAY_BUFFER, m_positions);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(m_positionData.size() * sizeof(float)), m_positionData.data(),
                 GL_STREAM_DRAW);
    glBindBuffer(GL_ARRAY_BUFFER, m_colours);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(m_colourData.size() * sizeof(float)), m_colourData.data(), GL_STREAM_DRAW);

    if (settings.mode == DrawMode::MassesAndSprings)
    {
        return;
    }
    // Vertex normals: the area-weighted sum of the normals of the surface triangles at each mass.
    m_normalData.assign(3 * n, 0.0f);
    const std::vector<std::uint32_t>& triangles = m_topology->surfaceTriangles;
    for (std::size_t t = 0; t + 2 < triangles.size(); t += 3)
    {
        const std::uint32_t a = triangles[t];
        const std::uint32_t b = triangles[t + 1];
        const std::uint32_t c = triangles[t + 2];
        const Vec3 normal = (positions[b] - positions[a]).cross(positions[c] - positions[a]);
        for (std::uint32_t k : {a, b, c})
        {
            m_normalData[3 * k] += float(normal.x());
            m_normalData[3 * k + 1] += float(normal.y());
            m_normalData[3 * k + 2] += float(normal.z());
        }
    }
    glBindBuffer(GL_ARRAY_BUFFER, m_normals);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(m_normalData.size() * sizeof(float)), m_normalData.data(), GL_STREAM_DRAW);
}

void Renderer::upload(VertexStream& stream, const std::vector<Vertex>& vertices)
{
    glBindBuffer(GL_ARRAY_BUFFER, stream.vbo);
    glBufferData(GL_ARRAY_BUFFER, GLsizeiptr(vertices.size() * sizeof(Vertex)), vertices.data(), GL_STREAM_DRAW);
    stream.count = GLsizei(vertices.size());
}

void Renderer::buildEnvironment(const SceneSnapshot& snapshot, bool showRoom)
{
    const bridge::RoomSpec& room = snapshot.spec->environment.room;
    const Vec3 roomCentre = (room.minCorner + room.maxCorner) / 2;

    std::vector<Vertex> roomFaces;
    std::vector<Vertex> solidFaces;
    std::vector<Vertex> lines;
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
            appendPolygon(roomFaces, corners, obstacle.normals[inner], colour);
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
            appendPolygon(solidFaces, corners, obstacle.normals[f], obstacle.touched[f] ? palette::touchedFace : base);
            for (std::size_t k = 0; k < corners.size(); ++k)
            {
                for (const Vec3* p : {&corners[k], &corners[(k + 1) % corners.size()]})
                {
                    Vertex v{};
                    put(v.position, *p);
                    put(v.colour, palette::edge);
                    lines.push_back(v);
                }
            }
        }
    }
    if (showRoom && room.enabled)
    {
        // A one-metre grid on the floor, lifted a hair above it so it does not fight the floor for depth.
        const Real y = room.minCorner.y() + Real(0.002);
        auto gridLine = [&](const Vec3& a, const Vec3& b)
        {
            for (const Vec3* p : {&a, &b})
            {
                Vertex v{};
                put(v.position, *p);
                put(v.colour, palette::floorGrid);
                lines.push_back(v);
            }
        };
        for (Real x = std::ceil(room.minCorner.x()); x <= room.maxCorner.x(); x += 1)
        {
            gridLine(Vec3(x, y, room.minCorner.z()), Vec3(x, y, room.maxCorner.z()));
        }
        for (Real z = std::ceil(room.minCorner.z()); z <= room.maxCorner.z(); z += 1)
        {
            gridLine(Vec3(room.minCorner.x(), y, z), Vec3(room.maxCorner.x(), y, z));
        }
    }
    upload(m_roomFaces, roomFaces);
    upload(m_solidFaces, solidFaces);
    upload(m_lines, lines);
}

void Renderer::buildOverlays(const SceneSnapshot& snapshot, const std::optional<std::pair<Index, Vec3>>& pick)
{
    std::vector<Vertex> lines;
    std::vector<Vertex> points;
    auto add = [](std::vector<Vertex>& out, const Vec3& p, const Rgb& colour)
    {
        Vertex v{};
        put(v.position, p);
        put(v.colour, colour);
        out.push_back(v);
    };
    for (const auto& [mass, target] : snapshot.grabs)
    {
        add(lines, mass, palette::scriptedGrab);
        add(lines, target, palette::scriptedGrab);
        add(points, mass, palette::scriptedGrab);
    }
    std::optional<std::pair<Index, Vec3>> shown = pick;
    if (!shown && snapshot.pickedMass)
    {
        shown = std::pair<Index, Vec3>(*snapshot.pickedMass, snapshot.pickTarget);
    }
    if (shown && shown->first < snapshot.positions.size())
    {
        const Vec3& x = snapshot.positions[shown->first];
        add(lines, x, palette::pick);
        add(lines, shown->second, palette::pick);
        add(points, x, palette::pick);
        add(points, shown->second, palette::pick);
    }
    // Bullet's twin (--compare) as a ghost over MaSSE's sheet: its links and nodes, nodes in contact coloured.
    if (snapshot.ghost)
    {
        const GhostShape& ghost = *snapshot.ghost;
        for (std::uint32_t node : ghost.links)
        {
            add(lines, ghost.nodes[node], palette::ghost);
        }
        for (std::size_t i = 0; i < ghost.nodes.size(); ++i)
        {
            add(points, ghost.nodes[i], ghost.touching[i] ? palette::ghostInContact : palette::ghost);
        }
    }
    upload(m_overlayLines, lines);
    upload(m_overlayPoints, points);
}

void Renderer::drawSheet(const DrawSettings& settings, const OrbitCamera& camera, const Viewport& viewport)
{
    glBindVertexArray(m_sheetVao);
    if (settings.mode == DrawMode::MassesAndSprings)
    {
        m_flat->use();
        const Real depth = std::max((m_sheetCentre - camera.eye()).norm(), camera.nearPlane());
        const Real spacingPixels = m_spacing / (depth * camera.pixelSizeAtUnitDepth(viewport));
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
        // Masses as round points about half a lattice spacing across on screen, within readable bounds.
        glUniform1f(m_flat->uniform("pointSize"), float(std::clamp(Real(0.45) * spacingPixels, Real(2), Real(9))));
        glUniform1i(m_flat->uniform("roundPoints"), 1);
        glDrawArrays(GL_POINTS, 0, GLsizei(m_positionData.size() / 3));
    }
    else
    {
        m_lit->use();
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, m_surfaceIndices);
        glDrawElements(GL_TRIANGLES, m_surfaceIndexCount, GL_UNSIGNED_INT, nullptr);
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
    uploadSheet(snapshot, settings);
    buildEnvironment(snapshot, settings.showRoom);
    buildOverlays(snapshot, pick);

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
