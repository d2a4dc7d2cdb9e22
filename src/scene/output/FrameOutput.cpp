#include "scene/output/FrameOutput.h"

#include "scene/output/FiniteOutput.h"

#include "scene/output/AtomicFile.h"
#include "scene/output/FrameWriter.h"
#include "scene/output/ObstacleVtp.h"

#include "core/contact/SelfContact.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>

namespace masse::scene
{
namespace
{
/// A file name part from an obstacle's name: letters, digits, - and _ kept, anything else becomes _.
std::string fileSafe(const std::string& name)
{
    std::string out = name;
    for (char& c : out)
    {
        const bool keep =
            (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') || c == '-' || c == '_';
        c = keep ? c : '_';
    }
    return out;
}

std::string stepSuffix(std::uint64_t step)
{
    char text[32];
    std::snprintf(text, sizeof(text), "%06llu", static_cast<unsigned long long>(step));
    return text;
}

/// Per-mass scalars of the heat model and the material, each named with its unit.
std::vector<std::pair<std::string, std::vector<double>>> materialScalars(const Scene& scene)
{
    std::vector<std::pair<std::string, std::vector<double>>> scalars;
    if (const ThermalModel* thermal = scene.thermal())
    {
        std::vector<double> celsius;
        celsius.reserve(thermal->temperature().size());
        for (Real kelvin : thermal->temperature())
        {
            celsius.push_back(kelvin - 273.15);
        }
        scalars.emplace_back("temperature_C", std::move(celsius));
    }
    if (const SheetThickness* thickness = scene.thickness())
    {
        scalars.emplace_back("thickness_m", thickness->thickness());
    }
    return scalars;
}
} // namespace

FrameOutput::FrameOutput(Scene& scene, const std::string& outDir) : m_outDir(outDir)
{
    const std::vector<std::string>& formats = scene.spec().output.formats;
    m_vtp = std::find(formats.begin(), formats.end(), "vtp") != formats.end();
    std::filesystem::create_directories(m_outDir + "/frames");
    m_surface = layerTriangles(scene.lattice(), 0);

    bridge::BulletEnvironment& environment = scene.environment();
    for (int i = 0; i < environment.obstacleCount(); ++i)
    {
        const bridge::Obstacle& obstacle = environment.obstacle(i);
        m_obstacleNames.push_back(obstacle.name);
        // The room's walls and ceiling would hide the scene in ParaView; its floor is what the sheet lands on.
        if (obstacle.partOfRoom && obstacle.name != "floor")
        {
            continue;
        }
        const std::string stem = "frames/obstacle_" + std::to_string(i) + "_" + fileSafe(obstacle.name);
        const bool moving = obstacle.path.isKinematic();
        m_obstacles.push_back({i, obstacle.name, moving ? stem : stem + ".vtp", moving});
        if (m_vtp && !moving)
        {
            writeFileAtomically(m_outDir + "/" + m_obstacles.back().file,
                                obstacleToVtp(obstacle.geometry, bridge::poseAt(obstacle.path, scene.time()),
                                              obstacle.name, i, std::nullopt));
        }
    }
    write(scene);
}

void FrameOutput::write(Scene& scene)
{
    requireFiniteState(scene); // a frame never holds an infinite speed
    const std::string step = stepSuffix(scene.steps());
    const std::string frame = "frames/frame_" + step;
    const Real time = scene.time();
    for (const std::string& format : scene.spec().output.formats)
    {
        const std::string path = m_outDir + "/" + frame + "." + format;
        if (format == "vtp")
        {
            FrameFields fields;
            fields.time = time;
            fields.contactObstacle = scene.contact().report().touchingObstacle();
            // Before the first step the contact solver has not looked yet: nothing touches.
            fields.contactObstacle.resize(scene.system().massCount(), -1);
            fields.obstacleNames = m_obstacleNames;
            if (const SelfContact* self = scene.selfContact())
            {
                fields.selfContact.assign(scene.system().massCount(), 0);
                self->markTouchingMasses(fields.selfContact);
            }
            fields.scalars = materialScalars(scene);
            writeFileAtomically(path, toVtp(scene.system(), m_surface, fields));
        }
        else
        {
            writeFileAtomically(path,
                                toObj(scene.system(), m_surface, scene.spec().name, scene.spec().output.objSprings));
        }
    }
    if (m_vtp)
    {
        m_collection.add(time, 0, "sheet", frame + ".vtp");
        int part = 1;
        for (const ObstaclePart& o : m_obstacles)
        {
            std::string file = o.file;
            if (o.moving)
            {
                file.append("_").append(step).append(".vtp");
                const bridge::Obstacle& obstacle = scene.environment().obstacle(o.index);
                writeFileAtomically(
                    m_outDir + "/" + file,
                    obstacleToVtp(obstacle.geometry, bridge::poseAt(obstacle.path, time), o.name, o.index, time));
            }
            m_collection.add(time, part++, o.name, file);
        }
    }
    m_lastStep = scene.steps();
    m_anyWritten = true;
}

void FrameOutput::finish(Scene& scene)
{
    if (!m_anyWritten || m_lastStep != scene.steps())
    {
        write(scene);
    }
    if (m_vtp)
    {
        writeFileAtomically(m_outDir + "/frames.pvd", m_collection.text());
    }
}
} // namespace masse::scene
