#include "scene/compare/Comparison.h"
#include "core/Format.h"

#include "scene/compare/ObstacleProbe.h"

#include "core/InputError.h"
#include "core/NumericalError.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace masse::scene
{
namespace
{
using Clock = std::chrono::steady_clock;

bool isStage(const std::string& name)
{
    return name == "contact" || name == "rest";
}

std::string twinLabel(const bridge::SoftBodyTwinSettings& s)
{
    return "Bullet (piterations=" + std::to_string(s.piterations) +
           (s.substeps != 1 ? ", substeps=" + std::to_string(s.substeps) : std::string()) + ")";
}

std::string twinKey(const bridge::SoftBodyTwinSettings& s)
{
    return "bullet_p" + std::to_string(s.piterations) + (s.substeps != 1 ? "_s" + std::to_string(s.substeps) : "");
}
} // namespace

void validate(const CompareOptions& options)
{
    for (std::size_t i = 0; i < options.bulletIterations.size(); ++i)
    {
        const int n = options.bulletIterations[i];
        if (n < 1 || n > 1000)
        {
            throw InputError("--bullet-iterations: each count must be a whole number in [1, 1000] (got " +
                             std::to_string(n) + ")");
        }
        for (std::size_t j = 0; j < i; ++j)
        {
            if (options.bulletIterations[j] == n)
            {
                throw InputError("--bullet-iterations: " + std::to_string(n) + " is given twice");
            }
        }
    }
    if (options.bulletSubsteps < 0 || options.bulletSubsteps > 10000)
    {
        throw InputError("--bullet-substeps: must be a whole number in [1, 10000] (got " +
                         std::to_string(options.bulletSubsteps) + ")");
    }
}

std::optional<Real> EngineResult::eventTime(const std::string& name, const std::string& object) const
{
    for (const StageEvent& e : events)
    {
        if (e.name == name && e.object == object)
        {
            return e.time;
        }
    }
    return std::nullopt;
}

Comparison::Comparison(SceneSpec spec, const CompareOptions& options, std::function<void(const std::string&)> log)
{
    validate(options);
    m_scene = std::make_unique<Scene>(std::move(spec));
    const SceneSpec& s = m_scene->spec();
    // Penetration only needs distances below the contact radius; 0.1 m leaves room for tunnel counting's "inside".
    m_searchDistance = std::max(Real(0.1), 4 * s.contact.radius);

    EngineResult masse;
    masse.key = "masse";
    masse.label = "MaSSE (" + std::string(integratorName(s.time.integrator)) + ")";
    masse.settings = {{"integrator", integratorName(s.time.integrator)},
                      {"dt", s.time.dt},
                      {"substeps_per_frame", m_scene->simulator().substepsFor(s.time.dt)},
                      {"contact", contactResponseName(s.contact.response)},
                      {"contact_radius", s.contact.radius}};
    masse.penetration = PenetrationStats(s.contact.radius);
    m_results.push_back(std::move(masse));

    buildTwins(options, log);
    collectApproximations();

    bridge::BulletEnvironment& environment = m_scene->environment();
    environment.setTime(0);
    const std::vector<Vec3>& start = m_scene->system().particles.position;
    const std::vector<Real> startDistances = signedDistances(environment, start, m_searchDistance);
    for (std::size_t k = 0; k < m_results.size(); ++k)
    {
        m_tunnels.push_back(std::make_unique<TunnelCounter>(start, startDistances, obstacleQuery(environment)));
    }
}

Comparison::~Comparison() = default;

void Comparison::buildTwins(const CompareOptions& options, const std::function<void(const std::string&)>& log)
{
    const SceneSpec& s = m_scene->spec();
    const std::vector<int> iterations =
        options.bulletIterations.empty() ? std::vector<int>{s.bullet.settings.piterations} : options.bulletIterations;
    const MassSpringSystem& sheet = m_scene->system();
    bridge::BulletEnvironment& environment = m_scene->environment();
    const std::string origin = s.path.empty() ? s.name : s.path;
    for (int n : iterations)
    {
        bridge::SoftBodyTwinSettings settings = s.bullet.settings;
        settings.piterations = n;
        if (options.bulletSubsteps > 0)
        {
            settings.substeps = options.bulletSubsteps;
        }
        Twin twin;
        try
        {
            if (s.bullet.calibrate)
            {
                if (sheet.forces.gravity.norm() == 0)
                {
                    throw InputError("bullet.calibrate: the calibration measures sag under gravity, and this "
                                     "scene's gravity is zero");
                }
                if (log)
                {
                    log("calibrating kLST for " + twinLabel(settings) + " (the sheet clamped on two edges)");
                }
                MassSpringSystem clamped = sheet;
                for (Index i = 0; i < clamped.massCount(); ++i)
                {
                    clamped.particles.setPinned(i, false);
                }
                bridge::clampOnTwoEdges(clamped, m_scene->lattice());
                twin.calibration = bridge::calibrateLinearStiffness(clamped, s.time.dt, settings);
                settings.kLST = twin.calibration->kLST;
            }
            twin.twin = std::make_unique<bridge::SoftBodyTwin>(sheet, environment, s.contact, s.time.dt, settings);
        }
        catch (const InputError& e)
        {
            throw InputError(origin + ": " + e.what());
        }
        twin.gravity = sheet.forces.gravity;
        twin.pinned = sheet.particles.pinned;
        for (int o = 0; o < environment.obstacleCount(); ++o)
        {
            twin.pathKeys.push_back(environment.obstacle(o).path.keys.size());
        }
        twin.touched.assign(std::size_t(environment.obstacleCount()), 0);
        twin.rest = RestTracker(m_scene->spec().run.restKineticEnergy, m_scene->spec().run.restHold);

        EngineResult result;
        result.key = twinKey(settings);
        result.label = twinLabel(settings);
        result.isBullet = true;
        result.penetration = PenetrationStats(s.contact.radius);
        const bridge::SoftBodyTwin& t = *twin.twin;
        const bridge::SoftBodyTwinSettings& used = t.settings();
        Real kMin = 1;
        Real kMax = 0;
        for (std::size_t j = 0; j < t.linkCount(); ++j)
        {
            kMin = std::min(kMin, t.linkStiffness(j));
            kMax = std::max(kMax, t.linkStiffness(j));
        }
        result.settings = {
            {"kLST", used.kLST ? nlohmann::json(*used.kLST) : nlohmann::json(nullptr)},
            {"kLST_links", {kMin, kMax}},
            {"kDP", *used.kDP},
            {"kDF", *used.kDF},
            {"kCHR", used.kCHR},
            {"kKHR", used.kKHR},
            {"margin", *used.margin},
            {"piterations", used.piterations},
            {"substeps", used.substeps},
            {"substep", t.substep()},
            {"sdf_cell_size", used.sdfCellSize},
            {"collisions", s.bullet.collisions},
        };
        if (twin.calibration)
        {
            const bridge::StiffnessCalibration& c = *twin.calibration;
            result.settings["calibration"] = {{"kLST", c.kLST},
                                              {"reachable", c.reachable},
                                              {"masse_sag", c.masse.sag},
                                              {"bullet_sag", c.bullet.sag},
                                              {"evaluations", c.evaluations}};
        }
        m_results.push_back(std::move(result));
        m_twins.push_back(std::move(twin));
    }
}

void Comparison::collectApproximations()
{
    auto add = [this](const std::string& subject, const std::string& message, const std::string& run)
    {
        for (Approximation& a : m_approximations)
        {
            if (a.subject == subject && a.message == message)
            {
                a.runs.push_back(run);
                return;
            }
        }
        m_approximations.push_back({subject, message, {run}});
    };
    const SceneSpec& s = m_scene->spec();
    bool grabs = false;
    bool pins = false;
    for (const ScriptAction& action : s.script)
    {
        grabs = grabs || action.kind == ScriptAction::Kind::Grab;
        pins = pins || action.kind == ScriptAction::Kind::Pin || action.kind == ScriptAction::Kind::Unpin;
    }
    for (std::size_t k = 0; k < m_twins.size(); ++k)
    {
        const std::string& run = m_results[k + 1].label;
        for (const bridge::TwinNote& note : m_twins[k].twin->notes())
        {
            add(note.subject, note.message, run);
        }
        if (grabs)
        {
            add("script.grab",
                "A grab acts on the twin's node of the same index as MaSSE's grabbed mass, with the same spring "
                "(target path, stiffness, damping, force cap), applied as a force at the start of every Bullet "
                "substep. A grab \"near\" a point takes the mass nearest that point in MaSSE's sheet, which need not "
                "be the twin's nearest node.",
                run);
        }
        if (pins)
        {
            add("script.pin",
                "A pin makes the twin's node massless where the twin's node is when the pin fires (MaSSE holds its "
                "own mass where it is); an unpin gives the node its mass back. Links keep the kLST derived at the "
                "start, for the pins then.",
                run);
        }
        if (m_twins[k].calibration && !m_twins[k].calibration->reachable)
        {
            const bridge::StiffnessCalibration& c = *m_twins[k].calibration;
            add("bullet.calibrate",
                "Even rigid links (kLST = 1) sag " + formatNumber("%.3g", c.bullet.sag / c.masse.sag) +
                    " times as much as MaSSE's sheet at this substep and pass count: the twin is softer than the "
                    "sheet, kLST = 1 is used.",
                run);
        }
        add("events",
            "Bullet's first contact with an obstacle is the first frame in which it reports a rigid contact for a "
            "node (a node within the margin), dated at the end of that frame; MaSSE's is dated at the end of the "
            "integrator substep that made it, the dating alone can part the two by up to one dt (" +
                formatNumber(s.time.dt) + " s). Rest uses the scene's threshold (kinetic energy below " +
                formatNumber(s.run.restKineticEnergy) + " J for " + formatNumber(s.run.restHold) + " s) for both.",
            run);
    }
}

void Comparison::mirrorScript(Twin& twin)
{
    const MassSpringSystem& sheet = m_scene->system();
    if (sheet.forces.gravity != twin.gravity)
    {
        twin.twin->setGravity(sheet.forces.gravity);
        twin.gravity = sheet.forces.gravity;
    }
    for (std::size_t i = 0; i < twin.pinned.size(); ++i)
    {
        if (sheet.particles.pinned[i] != twin.pinned[i])
        {
            twin.twin->setPinned(Index(i), sheet.particles.pinned[i] != 0);
            twin.pinned[i] = sheet.particles.pinned[i];
        }
    }
    // MaSSE's targets are aimed at the end of the frame just stepped; the twin moves them back along their velocity
    // to the start of each of its substeps.
    twin.twin->setUserSprings(sheet.userSprings, m_scene->time());
    const bridge::BulletEnvironment& environment = m_scene->environment();
    for (int o = 0; o < environment.obstacleCount(); ++o)
    {
        const std::vector<bridge::PoseKey>& path = environment.obstacle(o).path.keys;
        if (path.size() != twin.pathKeys[std::size_t(o)])
        {
            twin.twin->setObstaclePath(o, path);
            twin.pathKeys[std::size_t(o)] = path.size();
        }
    }
}

void Comparison::updateTwinEvents(Twin& twin, EngineResult& result)
{
    const bridge::SoftBodyTwin& t = *twin.twin;
    const bridge::BulletEnvironment& environment = m_scene->environment();
    for (int obstacle : t.touchingObstacle())
    {
        if (obstacle >= 0 && !twin.touched[std::size_t(obstacle)])
        {
            twin.touched[std::size_t(obstacle)] = 1;
            result.events.push_back({"contact", environment.obstacle(obstacle).name, t.time()});
        }
    }
    // The scene's rest rule, on the twin's contacts and energy; the script is the scene's, played on both engines.
    bool ready = !m_scene->scriptStillMoving();
    for (const std::string& name : m_scene->spec().run.restAfterContactWith)
    {
        const int index = environment.findObstacle(name);
        ready = ready && index >= 0 && twin.touched[std::size_t(index)];
    }
    if (twin.rest.update(t.time(), ready ? t.kineticEnergy() : Real(0), ready))
    {
        result.events.push_back({"rest", "sheet", twin.rest.since()});
    }
}

void Comparison::measure(EngineResult& result, TunnelCounter& tunnels, const std::vector<Vec3>& positions, Real energy,
                         double wallSeconds)
{
    const std::vector<Real> d = signedDistances(m_scene->environment(), positions, m_searchDistance);
    result.penetration.addFrame(d);
    result.framePenetration.push_back(result.penetration.lastFrameMax());
    tunnels.addFrame(positions, d);
    result.run.addFrame(time(), energy, wallSeconds);
}

bool Comparison::rested(std::size_t engine) const
{
    if (engine == 0)
    {
        return m_results[0].eventTime("rest", "sheet").has_value();
    }
    return m_twins[engine - 1].rest.rested();
}

bool Comparison::finished() const
{
    const SceneSpec& s = m_scene->spec();
    if (time() >= s.run.duration - 1e-9)
    {
        return true;
    }
    if (!s.run.stopAtRest)
    {
        return false;
    }
    for (std::size_t k = 0; k < m_results.size(); ++k)
    {
        if (m_results[k].failure.empty() && !rested(k))
        {
            return false;
        }
    }
    return true;
}

void Comparison::step()
{
    const Clock::time_point before = Clock::now();
    m_scene->step();
    const double masseWall = std::chrono::duration<double>(Clock::now() - before).count();
    for (std::size_t k = 0; k < m_twins.size(); ++k)
    {
        EngineResult& result = m_results[k + 1];
        if (!result.failure.empty())
        {
            continue;
        }
        mirrorScript(m_twins[k]);
        try
        {
            m_twins[k].twin->step();
        }
        catch (const NumericalError& e)
        {
            result.failure = e.what();
            continue;
        }
        updateTwinEvents(m_twins[k], result);
    }

    m_times.push_back(m_scene->time());
    m_scene->environment().setTime(m_scene->time());
    EngineResult& masse = m_results[0];
    for (; m_masseEventsSeen < m_scene->events().size(); ++m_masseEventsSeen)
    {
        const SceneEvent& e = m_scene->events()[m_masseEventsSeen];
        if (isStage(e.name))
        {
            masse.events.push_back({e.name, e.object, e.simTime});
        }
    }
    const std::vector<Vec3>& x = m_scene->system().particles.position;
    measure(masse, *m_tunnels[0], x, m_scene->kineticEnergy(), masseWall);
    for (std::size_t k = 0; k < m_twins.size(); ++k)
    {
        EngineResult& result = m_results[k + 1];
        if (!result.failure.empty())
        {
            continue;
        }
        const bridge::SoftBodyTwin& twin = *m_twins[k].twin;
        const std::vector<Vec3> nodes = twin.positions();
        measure(result, *m_tunnels[k + 1], nodes, twin.kineticEnergy(), twin.lastStepWallSeconds());
        result.distance.push_back(positionDistance(x, nodes));
    }
}

void Comparison::run(const std::function<void(Real, const std::string&)>& progress)
{
    std::string latest;
    std::vector<std::size_t> seen(m_results.size(), 0);
    while (!finished())
    {
        step();
        if (progress)
        {
            for (std::size_t k = 0; k < m_results.size(); ++k)
            {
                for (; seen[k] < m_results[k].events.size(); ++seen[k])
                {
                    const StageEvent& e = m_results[k].events[seen[k]];
                    latest = m_results[k].label.substr(0, m_results[k].label.find(' ')) + ": " + e.name + " " +
                             e.object + formatNumber(" at %.2f s", e.time);
                }
            }
            progress(time(), latest);
        }
    }
    finish();
}

void Comparison::finish()
{
    for (std::size_t k = 0; k < m_results.size(); ++k)
    {
        m_results[k].tunnels = m_tunnels[k]->count();
    }
}
} // namespace masse::scene
