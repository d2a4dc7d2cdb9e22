/// masse._masse: the C++ half of the Python module `masse` (python/masse/__init__.py is the other). A thin layer over
/// the scene library: scenes are read, checked, built, stepped, scripted, run and summarised by the same code as the
/// `masse` command; this file only converts between Python and C++ and keeps Python's promises (the GIL released
/// while stepping, read-only views that keep their scene alive, no crash from any call).

#include "scene/EngineEnvironment.h"
#include "scene/Runner.h"
#include "scene/Scene.h"
#include "scene/SceneFile.h"
#include "scene/SceneOverrides.h"
#include "scene/output/OutputFolder.h"
#include "scene/study/StudyResults.h"

#include "core/InputError.h"
#include "core/NumericalError.h"
#include "core/StateHash.h"
#include "core/parallel/TaskPool.h"

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <iostream>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace py = pybind11;

namespace masse::python
{
namespace
{
static_assert(sizeof(Vec3) == 3 * sizeof(Real), "a std::vector<Vec3> must be N x 3 contiguous doubles");
static_assert(sizeof(SpringEnds) == 2 * sizeof(Index), "spring ends must be M x 2 contiguous indices");
static_assert(sizeof(LatticeCoord) == 3 * sizeof(int), "lattice coordinates must be N x 3 contiguous ints");

/// The thread count masse.set_threads chose (0 until it is called: the environment's). Each scene has its own pool
/// and takes this count when it is built and at the start of each step loop.
std::atomic<int> chosenThreads{0};

/// What masse.threads() says: the count set_threads chose, else $MASSE_THREADS, else every core.
int moduleThreads()
{
    const int chosen = chosenThreads.load();
    return chosen > 0 ? chosen : scene::threadsFromEnvironment();
}

/// Ctrl+C while the GIL is released: every 0.1 s of stepping the GIL is taken back for a moment to let Python see a
/// signal (KeyboardInterrupt then stops the loop between two steps).
class InterruptCheck
{
public:
    void operator()()
    {
        const auto now = std::chrono::steady_clock::now();
        if (now - m_last < std::chrono::milliseconds(100))
        {
            return;
        }
        m_last = now;
        py::gil_scoped_acquire gil;
        if (PyErr_CheckSignals() != 0)
        {
            throw py::error_already_set();
        }
    }

private:
    std::chrono::steady_clock::time_point m_last = std::chrono::steady_clock::now();
};

/// nlohmann::json to Python (dict, list, str, int, float, bool, None).
py::object toPython(const nlohmann::json& value)
{
    switch (value.type())
    {
    case nlohmann::json::value_t::object:
    {
        py::dict d;
        for (const auto& [key, item] : value.items())
        {
            d[py::str(key)] = toPython(item);
        }
        return d;
    }
    case nlohmann::json::value_t::array:
    {
        py::list l;
        for (const nlohmann::json& item : value)
        {
            l.append(toPython(item));
        }
        return l;
    }
    case nlohmann::json::value_t::string:
        return py::str(value.get<std::string>());
    case nlohmann::json::value_t::boolean:
        return py::bool_(value.get<bool>());
    case nlohmann::json::value_t::number_integer:
        return py::int_(value.get<std::int64_t>());
    case nlohmann::json::value_t::number_unsigned:
        return py::int_(value.get<std::uint64_t>());
    case nlohmann::json::value_t::number_float:
        return py::float_(value.get<double>());
    default:
        return py::none();
    }
}

/// JSON text from Python (json.dumps of a scene or an action) parsed; a syntax error is the caller's input.
nlohmann::json parseJson(const std::string& text, const std::string& origin)
{
    nlohmann::json value = nlohmann::json::parse(text, nullptr, false);
    if (value.is_discarded())
    {
        throw InputError(origin + ": not valid JSON");
    }
    return value;
}

/// A read-only NumPy array over memory the scene owns; `owner` (the Python scene) is its base, so the memory lives
/// as long as the array does.
py::array view(py::dtype dtype, std::vector<py::ssize_t> shape, std::vector<py::ssize_t> strides, const void* data,
               py::handle owner)
{
    py::array array(std::move(dtype), std::move(shape), std::move(strides), data, owner);
    array.attr("flags").attr("writeable") = false;
    return array;
}

py::array vec3View(const std::vector<Vec3>& values, py::handle owner)
{
    return view(py::dtype::of<Real>(), {py::ssize_t(values.size()), 3},
                {py::ssize_t(sizeof(Vec3)), py::ssize_t(sizeof(Real))}, values.data(), owner);
}

template <typename T> py::array vectorView(const std::vector<T>& values, py::handle owner)
{
    return view(py::dtype::of<T>(), {py::ssize_t(values.size())}, {py::ssize_t(sizeof(T))}, values.data(), owner);
}

/// The scene spec as read, before it is built: what Scene and run() take.
struct Spec
{
    scene::SceneSpec spec;
};

scene::SceneFlags flagsOf(const std::vector<std::string>& settings, const std::string& size,
                          const std::string& duration, const std::string& dt, const std::string& integrator)
{
    scene::SceneFlags flags;
    flags.settings = settings;
    flags.size = size;
    flags.duration = duration;
    flags.dt = dt;
    flags.integrator = integrator;
    // The module reads the engine's environment where the `masse` command does: when a scene is read.
    flags.engine = scene::engineFromEnvironment(moduleThreads());
    scene::applySimdFromEnvironment();
    return flags;
}

/// A built scene with a lock: one step loop or change at a time, whichever Python thread asks.
class PyScene
{
public:
    explicit PyScene(const Spec& spec) : m_scene(std::make_unique<scene::Scene>(withThreads(spec.spec))) {}

    /// Takes the scene's lock, letting other Python threads run while it waits (the holder may be stepping without
    /// the GIL, and never waits for the GIL while holding the lock except to check for Ctrl+C, which releases it).
    std::unique_lock<std::mutex> lock()
    {
        std::unique_lock<std::mutex> held(m_mutex, std::try_to_lock);
        if (!held.owns_lock())
        {
            py::gil_scoped_release release;
            held.lock();
        }
        return held;
    }

    scene::Scene& scene() { return *m_scene; }

    void step(long long count)
    {
        if (count < 0)
        {
            throw py::value_error("step: n must be >= 0 (got " + std::to_string(count) + ")");
        }
        const auto held = lock();
        adoptThreads();
        py::gil_scoped_release release;
        InterruptCheck interrupted;
        for (long long k = 0; k < count; ++k)
        {
            m_scene->step();
            interrupted();
        }
    }

    void run(std::optional<double> until)
    {
        if (until && !(std::isfinite(*until) && *until <= scene::limits::maxDuration))
        {
            throw py::value_error("run: until must be a number of seconds up to " +
                                  std::to_string(scene::limits::maxDuration));
        }
        const auto held = lock();
        adoptThreads();
        py::gil_scoped_release release;
        InterruptCheck interrupted;
        // Without `until`, the scene's own end (its duration, or rest when it stops at rest), as `masse run` runs it.
        while (until ? m_scene->time() < *until - 1e-9 : !m_scene->finished())
        {
            m_scene->step();
            interrupted();
        }
    }

    /// Throws IndexError for a mass the sheet does not have.
    void requireMass(long long mass, const char* what) const
    {
        const std::size_t count = m_scene->system().massCount();
        if (mass < 0 || std::size_t(mass) >= count)
        {
            throw py::index_error(std::string(what) + ": mass " + std::to_string(mass) +
                                  " does not exist (the sheet has " + std::to_string(count) + " masses, 0 to " +
                                  std::to_string(count - 1) + ")");
        }
    }

    /// A script action in a scene file's words (JSON text, its time already set), read and checked as a file's is;
    /// every mass it names is checked first (IndexError).
    void act(const std::string& text)
    {
        const nlohmann::json document = parseJson(text, "action");
        const auto held = lock();
        scene::ScriptAction action = scene::readScriptAction(document, "action");
        if (action.kind == scene::ScriptAction::Kind::Grab && !action.grabNearest)
        {
            requireMass(action.mass, "grab");
        }
        for (Index mass : action.masses.masses)
        {
            requireMass(mass, scene::actionName(action.kind).c_str());
        }
        try
        {
            m_scene->addAction(std::move(action));
        }
        catch (const InputError& e)
        {
            throw InputError(std::string("action.") + e.what());
        }
    }

    void redirectGrab(const std::string& label, const std::array<double, 3>& target, double duration)
    {
        const auto held = lock();
        m_scene->redirectGrab(label, Vec3(target[0], target[1], target[2]), duration);
    }

    /// Sets positions or velocities (N x 3, finite) between steps; pinned masses keep zero velocity, and the engine
    /// is told that masses moved (cached integrator state is rebuilt).
    void setState(const py::array_t<double, py::array::c_style | py::array::forcecast>& values, bool velocities)
    {
        const char* name = velocities ? "set_velocities" : "set_positions";
        const std::size_t count = m_scene->system().massCount();
        if (values.ndim() != 2 || std::size_t(values.shape(0)) != count || values.shape(1) != 3)
        {
            std::string shape;
            for (py::ssize_t d = 0; d < values.ndim(); ++d)
            {
                shape += (d > 0 ? ", " : "") + std::to_string(values.shape(d));
            }
            throw py::value_error(std::string(name) + ": expected an array of shape (" + std::to_string(count) +
                                  ", 3) (got (" + shape + "))");
        }
        const double* data = values.data();
        for (std::size_t i = 0; i < 3 * count; ++i)
        {
            if (!std::isfinite(data[i]))
            {
                throw py::value_error(std::string(name) + ": mass " + std::to_string(i / 3) +
                                      " has a value that is not finite");
            }
        }
        const auto held = lock();
        Particles& p = m_scene->system().particles;
        std::vector<Vec3>& target = velocities ? p.velocity : p.position;
        for (std::size_t i = 0; i < count; ++i)
        {
            target[i] = Vec3(data[3 * i], data[3 * i + 1], data[3 * i + 2]);
            if (velocities && p.pinned[i])
            {
                target[i].setZero();
            }
        }
        m_scene->system().markChanged();
    }

    py::list events()
    {
        std::vector<scene::SceneEvent> copy;
        {
            const auto held = lock();
            copy = m_scene->events();
        }
        py::list list;
        for (const scene::SceneEvent& e : copy)
        {
            py::dict event;
            event["name"] = e.name;
            event["object"] = e.object;
            event["sim_time"] = e.simTime;
            event["wall_time"] = e.wallTime;
            list.append(event);
        }
        return list;
    }

    py::object summary()
    {
        nlohmann::json summary;
        {
            const auto held = lock();
            summary = scene::summarize(*m_scene, m_scene->wallSeconds());
        }
        return toPython(summary);
    }

    std::uint64_t stateHash()
    {
        const auto held = lock();
        return masse::stateHash(m_scene->system().particles);
    }

    /// Temperatures in C (a copy: the engine keeps kelvin), or None without a heat model.
    py::object temperature()
    {
        std::vector<Real> celsius;
        {
            const auto held = lock();
            const ThermalModel* thermal = m_scene->thermal();
            if (!thermal)
            {
                return py::none();
            }
            for (Real kelvin : thermal->temperature())
            {
                celsius.push_back(kelvin - 273.15);
            }
        }
        return py::array_t<double>(py::ssize_t(celsius.size()), celsius.data());
    }

private:
    static scene::SceneSpec withThreads(scene::SceneSpec spec)
    {
        spec.engine.threads = moduleThreads();
        return spec;
    }

    /// The count masse.set_threads chose since this scene was built or last stepped (with the scene's lock held).
    void adoptThreads()
    {
        const int threads = moduleThreads();
        if (threads != m_scene->simulator().threadCount())
        {
            m_scene->setThreadCount(threads);
        }
    }

    std::unique_ptr<scene::Scene> m_scene;
    std::mutex m_mutex;
};

Spec specFromFile(const std::string& path, const std::vector<std::string>& settings, const std::string& size,
                  const std::string& duration, const std::string& dt, const std::string& integrator)
{
    return Spec{scene::loadScene(path, flagsOf(settings, size, duration, dt, integrator))};
}

Spec specFromDocument(const std::string& text, const std::string& baseDirectory, const std::string& origin,
                      const std::vector<std::string>& settings, const std::string& size, const std::string& duration,
                      const std::string& dt, const std::string& integrator)
{
    return Spec{scene::parseSceneWith(parseJson(text, origin), flagsOf(settings, size, duration, dt, integrator),
                                      baseDirectory, origin)};
}

/// What `masse run` does once the scene is read: frames and formats, the output folder's rules, the run, the
/// summary. Returns the summary and the warnings the command would print.
py::tuple runSpec(const Spec& given, const std::string& out, bool force, std::optional<int> framesEvery,
                  const std::vector<std::string>& formats, bool progress)
{
    scene::SceneSpec spec = given.spec;
    spec.engine.threads = moduleThreads();
    scene::applyFrameFlags(spec, framesEvery, formats);
    nlohmann::json summary;
    std::string warnings;
    {
        py::gil_scoped_release release;
        // Everything that can be wrong with the input is found before the output folder is touched.
        scene::OutputFolder folder(out, force);
        scene::Scene scene(spec);
        scene::RunOptions options;
        options.outDir = folder.staging();
        options.showProgress = progress;
        std::ostringstream quiet;
        const scene::RunResult result = scene::runScene(scene, options, progress ? std::cerr : quiet);
        folder.commit();
        summary = result.summary;
        warnings = quiet.str();
        if (!isExplicit(spec.time.integrator))
        {
            const std::string cap = scene::solverCapWarning(scene.simulator().solverTally(), spec.time.implicit);
            if (!cap.empty())
            {
                warnings += cap + "\n";
            }
        }
    }
    return py::make_tuple(toPython(summary), warnings);
}

/// A study folder's results as `masse sweep --collect` reads them.
py::dict collect(const std::string& dir)
{
    const scene::StudyResults results = scene::collectResults(dir);
    py::list parameters;
    for (const scene::StudyParameter& p : results.record.parameters)
    {
        parameters.append(py::dict(py::arg("name") = p.name, py::arg("unit") = p.unit));
    }
    py::list outputs;
    for (const scene::StudyOutput& o : results.record.outputs)
    {
        outputs.append(py::dict(py::arg("name") = o.name, py::arg("path") = o.path, py::arg("unit") = o.unit));
    }
    py::list cases;
    for (const scene::CollectedCase& c : results.cases)
    {
        py::dict values;
        for (std::size_t k = 0; k < c.values.size() && k < results.record.parameters.size(); ++k)
        {
            values[py::str(results.record.parameters[k].name)] = toPython(c.values[k]);
        }
        py::dict collected;
        for (std::size_t k = 0; k < c.outputs.size() && k < results.record.outputs.size(); ++k)
        {
            collected[py::str(results.record.outputs[k].name)] = toPython(c.outputs[k]);
        }
        cases.append(py::dict(py::arg("case") = c.index, py::arg("status") = c.status,
                              py::arg("exit_code") = c.exitCode, py::arg("message") = c.message,
                              py::arg("values") = values, py::arg("outputs") = collected));
    }
    return py::dict(py::arg("name") = results.record.name, py::arg("scene") = results.record.scene,
                    py::arg("parameters") = parameters, py::arg("outputs") = outputs, py::arg("cases") = cases,
                    py::arg("done") = results.done, py::arg("failed") = results.failed,
                    py::arg("not_run") = results.notRun);
}

void setThreads(int threads)
{
    requireThreadCount(threads);
    chosenThreads.store(threads);
}
} // namespace
} // namespace masse::python

PYBIND11_MODULE(_masse, m)
{
    using namespace masse;
    using namespace masse::python;
    m.doc() = "MaSSE's scene library from Python (the C++ half of the masse package; use `import masse`).";

    // Bad input, with the message the command prints; a ValueError, since that is what it is to Python.
    static py::exception<InputError> sceneError(m, "SceneError", PyExc_ValueError);
    // A run that went wrong (diverged, left double precision's range): the command's exit code 1.
    static py::exception<NumericalError> simulationError(m, "SimulationError", PyExc_RuntimeError);
    py::register_exception_translator(
        [](std::exception_ptr error)
        {
            try
            {
                if (error)
                {
                    std::rethrow_exception(error);
                }
            }
            catch (const InputError& e)
            {
                sceneError(e.what());
            }
            catch (const NumericalError& e)
            {
                simulationError(e.what());
            }
        });

    py::class_<Spec>(m, "_Spec");
    m.def("_spec_from_file", &specFromFile);
    m.def("_spec_from_document", &specFromDocument);
    m.def("_run", &runSpec);
    m.def("_collect", &collect);
    m.def("set_threads", &setThreads, py::arg("n"),
          "Threads for the engine's kernels (1 to 1024); results are the same bits at any count.");
    m.def("threads", &moduleThreads, "Threads the engine's kernels use.");

    py::class_<PyScene>(m, "_Scene")
        .def(py::init<const Spec&>())
        .def("step", &PyScene::step, py::arg("n") = 1)
        .def("run", &PyScene::run, py::arg("until") = py::none())
        .def("_act", &PyScene::act)
        .def("_redirect_grab", &PyScene::redirectGrab)
        .def("set_positions", [](PyScene& s, const py::array_t<double, py::array::c_style | py::array::forcecast>& a)
             { s.setState(a, false); })
        .def("set_velocities", [](PyScene& s, const py::array_t<double, py::array::c_style | py::array::forcecast>& a)
             { s.setState(a, true); })
        .def("state_hash", &PyScene::stateHash)
        .def("summary", &PyScene::summary)
        .def_property_readonly("events", &PyScene::events)
        .def_property_readonly("time", [](PyScene& s) { return s.scene().time(); })
        .def_property_readonly("steps", [](PyScene& s) { return s.scene().steps(); })
        .def_property_readonly("finished", [](PyScene& s) { return s.scene().finished(); })
        .def_property_readonly("name", [](PyScene& s) { return s.scene().spec().name; })
        .def_property_readonly("dt", [](PyScene& s) { return s.scene().spec().time.dt; })
        .def_property_readonly("duration", [](PyScene& s) { return s.scene().spec().run.duration; })
        .def_property_readonly("size",
                               [](PyScene& s)
                               {
                                   const LatticeSpec& l = s.scene().lattice().spec;
                                   return py::make_tuple(l.countX, l.layers, l.countZ);
                               })
        .def_property_readonly("heaters", [](PyScene& s) { return s.scene().spec().heat.heaterNames; })
        .def_property_readonly("mass_count", [](PyScene& s) { return s.scene().system().massCount(); })
        .def("_require_mass", &PyScene::requireMass)
        .def("index",
             [](PyScene& s, int layer, int row, int column)
             {
                 const Lattice& l = s.scene().lattice();
                 if (layer < 0 || layer >= l.spec.layers || row < 0 || row >= l.layerCountZ(layer) || column < 0 ||
                     column >= l.layerCountX(layer))
                 {
                     throw py::index_error("index: (layer " + std::to_string(layer) + ", row " + std::to_string(row) +
                                           ", column " + std::to_string(column) + ") is not in the sheet");
                 }
                 return l.index(layer, row, column);
             })
        .def_property_readonly("positions", [](py::object self)
                               { return vec3View(self.cast<PyScene&>().scene().system().particles.position, self); })
        .def_property_readonly("velocities", [](py::object self)
                               { return vec3View(self.cast<PyScene&>().scene().system().particles.velocity, self); })
        .def_property_readonly(
            "pinned",
            [](py::object self)
            {
                const std::vector<std::uint8_t>& pinned = self.cast<PyScene&>().scene().system().particles.pinned;
                // 0 or 1 in one byte: NumPy's bool exactly.
                return view(py::dtype("bool"), {py::ssize_t(pinned.size())}, {1}, pinned.data(), self);
            })
        .def_property_readonly("masses", [](py::object self)
                               { return vectorView(self.cast<PyScene&>().scene().system().particles.mass, self); })
        .def_property_readonly("thickness",
                               [](py::object self) -> py::object
                               {
                                   const SheetThickness* t = self.cast<PyScene&>().scene().thickness();
                                   if (!t)
                                   {
                                       return py::none();
                                   }
                                   return vectorView(t->thickness(), self);
                               })
        .def_property_readonly("temperature", &PyScene::temperature)
        .def_property_readonly("rest_positions", [](py::object self)
                               { return vec3View(self.cast<PyScene&>().scene().lattice().position, self); })
        .def_property_readonly("coords",
                               [](py::object self)
                               {
                                   const std::vector<LatticeCoord>& c = self.cast<PyScene&>().scene().lattice().coord;
                                   return view(py::dtype::of<int>(), {py::ssize_t(c.size()), 3},
                                               {py::ssize_t(sizeof(LatticeCoord)), py::ssize_t(sizeof(int))}, c.data(),
                                               self);
                               })
        .def_property_readonly(
            "springs",
            [](py::object self)
            {
                const std::vector<SpringEnds>& e = self.cast<PyScene&>().scene().system().springs.ends();
                return view(py::dtype::of<Index>(), {py::ssize_t(e.size()), 2},
                            {py::ssize_t(sizeof(SpringEnds)), py::ssize_t(sizeof(Index))}, e.data(), self);
            });
}
