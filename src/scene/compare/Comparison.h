#pragma once
/// MaSSE and its Bullet soft-body twin run side by side on one scene (`masse compare`): the same sheet, obstacles
/// and dt, stepped frame by frame, each engine's masses measured after every frame by the same functions
/// (ObstacleProbe.h against the scene's obstacles, CompareMetrics.h), so the figures differ only by what the engines
/// did.
///
/// The twins are built from the scene at t = 0, one per Bullet setting asked for (piterations swept, substeps). The
/// scene's script drives MaSSE as usual; after each MaSSE frame its effect is mirrored onto every twin before the
/// twin steps the same frame: gravity, pins, the dynamic springs of grabs (targets moving on along their velocity
/// within the frame) and the paths of moved obstacles. What a twin does differently is listed as approximations:
/// the twin's own notes, plus what the mirroring cannot make equal.

#include "scene/Scene.h"

#include "bridge/SoftBodyTwin.h"
#include "bridge/StiffnessCalibration.h"
#include "scene/compare/CompareMetrics.h"

#include <nlohmann/json.hpp>

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace masse::scene
{
struct CompareOptions
{
    /// One Bullet run per count of position-solver passes; empty: one run with the scene's bullet.piterations.
    std::vector<int> bulletIterations;
    /// Bullet substeps per frame for every run; 0: the scene's bullet.substeps.
    int bulletSubsteps = 0;
};

/// Throws InputError naming the flag for a count out of range or given twice.
void validate(const CompareOptions& options);

/// A stage of the run: "contact" (the first with the obstacle named by object) or "rest" (object "sheet").
struct StageEvent
{
    std::string name;
    std::string object;
    Real time = 0; ///< s, simulated
};

/// One engine's run as measured.
struct EngineResult
{
    std::string key;   ///< "masse", "bullet_p4": names its columns in series.csv
    std::string label; ///< "MaSSE (symplectic)", "Bullet (piterations=4)"
    bool isBullet = false;
    nlohmann::json settings; ///< what the engine was run with
    std::vector<StageEvent> events;
    PenetrationStats penetration{0.01};
    TunnelCount tunnels;
    RunRecord run;
    std::vector<Real> framePenetration; ///< m, the deepest sphere of each frame
    /// Bullet only: distance between its nodes and MaSSE's masses at each frame.
    std::vector<PositionDistance> distance;
    std::string failure; ///< why the engine stopped early (a Bullet run that diverged), or ""

    /// Time of the first event with this name and object, if any.
    std::optional<Real> eventTime(const std::string& name, const std::string& object) const;
};

/// A way the comparison is not like for like, and the runs it concerns.
struct Approximation
{
    std::string subject; ///< the scene key or topic
    std::string message;
    std::vector<std::string> runs; ///< labels of the Bullet runs it applies to
};

class Comparison
{
public:
    /// Builds the scene and one twin per Bullet setting (calibrating kLST first when the scene asks); throws
    /// InputError for anything the scene or the twin refuses. `log` receives progress lines of slow set-up steps.
    Comparison(SceneSpec spec, const CompareOptions& options, std::function<void(const std::string&)> log = {});
    ~Comparison();

    /// The run is over: the scene's duration is reached, or (when the scene stops at rest) every engine still
    /// running has come to rest.
    bool finished() const;
    /// One frame of every engine, then the measurements.
    void step();
    /// Steps until finished, then finish(); `progress` (if set) is called after every frame.
    void run(const std::function<void(Real simTime, const std::string& latest)>& progress = {});
    /// Sets each result's tunnel count (a segment test per entered mass, so not done every frame).
    void finish();

    Real time() const { return m_times.empty() ? Real(0) : m_times.back(); }
    const std::vector<Real>& frameTimes() const { return m_times; }
    /// MaSSE first, then the Bullet runs in the order asked.
    const std::vector<EngineResult>& results() const { return m_results; }
    const std::vector<Approximation>& approximations() const { return m_approximations; }
    const Scene& scene() const { return *m_scene; }
    /// The MaSSE scene, for a viewer's pick spring or heater switches: what it changes is mirrored onto the twins.
    Scene& scene() { return *m_scene; }
    /// The twin of Bullet run k (0-based, in results() order minus MaSSE).
    const bridge::SoftBodyTwin& twin(std::size_t k) const { return *m_twins[k].twin; }

    /// compare.json. SI units (m, s, J). Top level: scene, scene_file, structure, size, masses, springs, dt, frames,
    /// sim_seconds, contact_radius, units, measurement (how each figure is measured, in words), engines,
    /// approximations [{subject, message, runs}], files. Each engine: key, label, engine ("masse" or "bullet"),
    /// settings, events [{name, object, sim_time}], penetration {max, mean, mean_when_penetrating, final_max,
    /// penetrating_fraction}, tunnelled {count, inside, beyond, entered, started_inside}, kinetic_energy {final,
    /// max}, frames, simulated_seconds, wall_seconds, wall_ms_per_simulated_second, failure (null or why it
    /// stopped); a Bullet run also distance_to_masse {final {rms, max, mass}, final_time, events [{name, object,
    /// masse_time, bullet_time, at_masse_time, at_bullet_time}]}.
    nlohmann::json report() const;
    /// The side-by-side table printed by `masse compare`.
    std::string table() const;
    /// One row per frame: time, then per engine its frame penetration (mm) and kinetic energy (J), and for each
    /// Bullet run its RMS and maximum distance to MaSSE (mm).
    std::string seriesCsv() const;
    /// Writes compare.json, series.csv, penetration.png, kinetic_energy.png and distance.png into `directory`
    /// (created if missing), each atomically.
    void writeOutputs(const std::string& directory) const;

private:
    struct Twin
    {
        std::unique_ptr<bridge::SoftBodyTwin> twin;
        std::optional<bridge::StiffnessCalibration> calibration;
        Vec3 gravity;
        std::vector<std::uint8_t> pinned;
        std::vector<std::size_t> pathKeys; ///< keys of each obstacle's path the twin has
        std::vector<std::uint8_t> touched; ///< per obstacle
        RestTracker rest;
    };
    void buildTwins(const CompareOptions& options, const std::function<void(const std::string&)>& log);
    void collectApproximations();
    void mirrorScript(Twin& twin);
    void updateTwinEvents(Twin& twin, EngineResult& result);
    void measure(EngineResult& result, TunnelCounter& tunnels, const std::vector<Vec3>& positions, Real energy,
                 double wallSeconds);
    bool rested(std::size_t engine) const;

    std::unique_ptr<Scene> m_scene;
    std::vector<Twin> m_twins;
    std::vector<EngineResult> m_results;
    std::vector<std::unique_ptr<TunnelCounter>> m_tunnels; ///< per engine
    std::vector<Approximation> m_approximations;
    std::vector<Real> m_times;
    std::size_t m_masseEventsSeen = 0;
    Real m_searchDistance = 0.1;
};
} // namespace masse::scene
