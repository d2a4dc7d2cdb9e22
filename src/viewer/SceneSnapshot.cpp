#include "SceneSnapshot.h"

#include "SceneGeometry.h"
#include "ScreenRegions.h"

#include <algorithm>
#include <cmath>

namespace masse::viewer
{
namespace
{
std::shared_ptr<const SheetTopology> buildTopology(const scene::Scene& scene)
{
    auto topology = std::make_shared<SheetTopology>();
    const Lattice& lattice = scene.lattice();
    topology->springIndices.reserve(2 * lattice.springCount());
    for (const SpringEnds& ends : scene.system().springs.ends())
    {
        topology->springIndices.push_back(std::uint32_t(ends.a));
        topology->springIndices.push_back(std::uint32_t(ends.b));
    }
    topology->surfaceTriangles = sheetSurfaceTriangles(lattice);
    topology->spacing = lattice.smallerSpacing();
    topology->layers = lattice.spec.layers;
    for (int stride = 2; stride <= maxMassStride; stride *= 2)
    {
        topology->coarseMasses.push_back(massesAtStride(lattice, stride));
        topology->coarseSurfaces.push_back(coarseSurfaceTriangles(lattice, stride));
    }
    return topology;
}

void captureObstacles(scene::Scene& scene, std::vector<ObstacleShape>& out)
{
    const bridge::BulletEnvironment& environment = scene.environment();
    const std::vector<std::pair<int, int>>& touched = scene.contact().report().touchedFaces();
    out.resize(std::size_t(environment.obstacleCount()));
    for (int i = 0; i < environment.obstacleCount(); ++i)
    {
        const bridge::Obstacle& obstacle = environment.obstacle(i);
        ObstacleShape& shape = out[std::size_t(i)];
        shape.name = obstacle.name;
        shape.partOfRoom = obstacle.partOfRoom;
        shape.position = obstacle.pose.position;
        shape.kinematic = obstacle.path.isKinematic();
        shape.velocity = obstacle.motion.linear;
        const Real temperature = scene.obstacleTemperature(i);
        shape.hasTemperature = !std::isnan(temperature);
        shape.temperatureC = shape.hasTemperature ? temperature - 273.15 : 0;
        shape.vertices = obstacleVertices(obstacle);
        const auto& faces = obstacle.geometry.faces;
        shape.faces.resize(faces.size());
        shape.normals.resize(faces.size());
        shape.touched.assign(faces.size(), false);
        for (std::size_t f = 0; f < faces.size(); ++f)
        {
            shape.faces[f].assign(faces[f].vertices.begin(), faces[f].vertices.end());
            shape.normals[f] = obstacle.pose.orientation * faces[f].normal;
            shape.touched[f] = std::binary_search(touched.begin(), touched.end(), std::pair<int, int>(i, int(f)));
        }
    }
}
} // namespace

std::string scalarMissingReason(const scene::Scene& scene, const std::string& scalar)
{
    if (scalar == "temperature" && !scene.thermal())
    {
        return "this scene has no heat: temperature needs a \"heat\" section";
    }
    if ((scalar == "thickness" || scalar == "thickness_ratio") && !scene.thickness())
    {
        return "this scene has no material: thickness needs a \"material\"";
    }
    return "";
}

std::string missingScalarReason(const SceneSnapshot& snapshot, const std::string& scalar)
{
    for (const auto& [name, reason] : snapshot.missingScalars)
    {
        if (name == scalar)
        {
            return reason;
        }
    }
    return "";
}

void captureSnapshot(ViewerSession& session, const MassScalarRegistry& scalars, const std::string& scalar,
                     const SceneSnapshot* previous, SceneSnapshot& out)
{
    scene::Scene& scene = session.scene();
    out.generation = session.generation();
    if (previous && previous->generation == out.generation && previous->topology)
    {
        out.spec = previous->spec;
        out.topology = previous->topology;
    }
    else
    {
        out.spec = std::make_shared<const scene::SceneSpec>(scene.spec());
        out.topology = buildTopology(scene);
    }
    out.time = scene.time();
    out.paused = session.paused();
    out.error = session.error();
    out.notice = session.notice();
    MassSpringSystem& system = scene.system();
    out.springCount = system.springCount();
    out.touchingCount = scene.contact().report().touchingCount();
    out.events = scene.events();

    const Particles& particles = system.particles;
    const std::size_t n = particles.size();
    out.positions.assign(particles.position.begin(), particles.position.end());
    out.flags.resize(n);
    const std::vector<int>& touching = scene.contact().report().touchingObstacle();
    for (std::size_t i = 0; i < n; ++i)
    {
        out.flags[i] =
            particles.pinned[i] ? massPinned : (i < touching.size() && touching[i] >= 0 ? massInContact : massFree);
    }
    out.selfTouchingCount = 0;
    if (const SelfContact* self = scene.selfContact())
    {
        // Touching the sheet itself shows over touching an obstacle: the rarer news, where a fold has closed.
        std::vector<std::uint8_t> marks(n, 0);
        self->markTouchingMasses(marks);
        for (std::size_t i = 0; i < n; ++i)
        {
            if (marks[i] && !particles.pinned[i])
            {
                out.flags[i] = massInSelfContact;
                ++out.selfTouchingCount;
            }
        }
    }
    out.missingScalars.clear();
    for (const MassScalar& registered : scalars.all())
    {
        if (std::string reason = scalarMissingReason(scene, registered.name); !reason.empty())
        {
            out.missingScalars.emplace_back(registered.name, std::move(reason));
        }
    }
    out.scalarName = scalar;
    out.scalarMissing = scalar.empty() ? "" : scalarMissingReason(scene, scalar);
    out.scalar.clear();
    out.scalarFixedRange.reset();
    if (const MassScalar* found = scalars.find(scalar); found && out.scalarMissing.empty())
    {
        found->evaluate(scene, out.scalar);
        if (found->fixedRange)
        {
            out.scalarFixedRange = found->fixedRange(scene);
        }
        out.scalar.resize(n, 0.0f);
    }

    captureObstacles(scene, out.obstacles);
    out.grabs.clear();
    for (const auto& [mass, id] : scene.script().activeGrabs())
    {
        if (const UserSpring* spring = system.userSprings.find(id))
        {
            out.grabs.emplace_back(particles.position[mass], spring->target);
        }
    }
    out.pickedMass = session.pickedMass();
    out.pickTarget = session.pickTarget().value_or(Vec3::Zero());

    out.ghost.reset();
    if (const scene::Comparison* comparison = session.comparison())
    {
        GhostShape ghost;
        const bridge::SoftBodyTwin& twin = comparison->twin(0);
        ghost.nodes = twin.positions();
        for (std::size_t link = 0; link < twin.linkCount(); ++link)
        {
            const SpringEnds ends = twin.linkEnds(link);
            ghost.links.push_back(std::uint32_t(ends.a));
            ghost.links.push_back(std::uint32_t(ends.b));
        }
        const std::vector<int>& twinTouching = twin.touchingObstacle();
        ghost.touching.resize(ghost.nodes.size());
        for (std::size_t i = 0; i < ghost.nodes.size(); ++i)
        {
            ghost.touching[i] = i < twinTouching.size() && twinTouching[i] >= 0;
        }
        ghost.touchingCount = twin.touchingCount();
        ghost.masseDeepest = comparison->results().front().penetration.max();
        ghost.bulletDeepest = comparison->results().at(1).penetration.max();
        out.ghost = std::move(ghost);
    }

    out.section.clear();
    if (const std::optional<scene::SectionSettings>& section = session.section())
    {
        out.section = scene::thicknessSection(scene, *section);
        out.sectionAxis = section->axis;
    }
    out.thinnest.reset();
    if (const SheetThickness* thickness = scene.thickness(); thickness && !thickness->thickness().empty())
    {
        out.thinnest = std::pair<Index, Real>(thickness->thinnestMass(), thickness->minimumThickness());
    }
    ProcessState& process = out.process;
    process.forming = scene.pressure() != nullptr;
    process.pressure = scene.formingPressure();
    process.heaterPower.clear();
    for (std::size_t i = 0; i < scene.spec().heat.heaterNames.size(); ++i)
    {
        process.heaterPower.push_back(scene.heaterPower(i));
    }
    process.recordedActions = scene.addedActions().size();
    process.mousePulled = session.mousePulled();
    process.saveable = session.source().has_value();

    out.heat.reset();
    if (const ThermalModel* thermal = scene.thermal())
    {
        HeatState heat;
        heat.ambientC = thermal->settings().airTemperature - 273.15;
        for (std::size_t i = 0; i < scene.spec().heat.heaterNames.size(); ++i)
        {
            heat.heatersOn.push_back(scene.heaterOn(i));
        }
        const std::vector<Real>& t = thermal->temperature();
        if (!t.empty())
        {
            const auto [low, high] = std::minmax_element(t.begin(), t.end());
            heat.lowestC = *low - 273.15;
            heat.highestC = *high - 273.15;
        }
        if (const SheetThickness* thickness = scene.thickness())
        {
            heat.thinnest = thickness->minimumThickness();
            heat.initialThickness = thickness->initialThickness();
        }
        out.heat = std::move(heat);
    }
}
} // namespace masse::viewer
