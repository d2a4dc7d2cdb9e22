"""MaSSE from Python: scenes, runs and studies, with the sheet's state as NumPy arrays.

The C++ extension ``masse._masse`` does the work through MaSSE's scene library, the same code as the ``masse``
command; this file gives it Python's habits (keyword arguments, dicts for scene keys, iterables of masses). The
guide with the examples is docs/python.md.

    import masse
    scene = masse.Scene.load("data/scenes/drape-forming.json", {"heat.heaters[0].power": 8000}, size="8x2x8")
    scene.run(until=10.0)
    scene.positions        # (N, 3) float64, a read-only view of the engine's memory
    masse.run("data/scenes/sag.json", out="out/sag")   # what `masse run` does; returns summary.json as a dict
"""

import json
import math
import os
import shutil
import subprocess
import warnings

import numpy as np

from . import _masse
from ._masse import SceneError, SimulationError, set_threads, threads

__all__ = ["Scene", "SceneError", "SimulationError", "run", "sweep", "collect", "set_threads", "threads", "executable"]


def _plain(value):
    """A value as the JSON a scene file would hold: NumPy scalars and arrays as numbers and lists, tuples as lists,
    paths as text. A number that is not finite becomes its text ("nan"), which the scene reader refuses by name, as
    it refuses ``--set KEY=nan``."""
    if isinstance(value, dict):
        return {_key(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    if isinstance(value, np.ndarray):
        return _plain(value.tolist())
    if isinstance(value, np.generic):
        return _plain(value.item())
    if isinstance(value, float) and not math.isfinite(value):
        return str(value)
    if isinstance(value, os.PathLike):
        return os.fspath(value)
    return value


def _key(key):
    if not isinstance(key, str):
        raise TypeError("scene keys are text, such as 'heat.heaters[0].power' (got %r)" % (key,))
    return key


def _json(value):
    return json.dumps(_plain(value))


def _setting_value(value):
    """A value as --set takes it: JSON, or the text itself when it is text that does not read as JSON ("implicit"),
    as one writes it on the command line (so that messages quote the same setting)."""
    value = _plain(value)
    if isinstance(value, str):
        try:
            json.loads(value)
        except ValueError:
            return value
    return json.dumps(value, separators=(",", ":"))


def _settings(overrides):
    """{"heat.heaters[0].power": 8000} as the command's --set settings, KEY=VALUE."""
    if overrides is None:
        return []
    if not hasattr(overrides, "items"):
        raise TypeError("overrides: expected a dict of scene keys and values, such as "
                        "{'heat.heaters[0].power': 8000} (got %s)" % type(overrides).__name__)
    return ["%s=%s" % (_key(key), _setting_value(value)) for key, value in overrides.items()]


def _flag(value, name):
    """A value for --size, --duration, --dt or --integrator as the command reads it ("" when not given)."""
    if value is None:
        return ""
    if name == "size" and isinstance(value, (tuple, list)):
        return "x".join(str(v) for v in value)
    if isinstance(value, bool) or not isinstance(value, (str, int, float, np.integer, np.floating)):
        raise TypeError("%s: expected %s (got %s)" % (name, "text such as '16x2x16' or (16, 2, 16)" if name == "size"
                                                      else "a number or text", type(value).__name__))
    return repr(float(value)) if isinstance(value, (float, np.floating)) else str(value)


def _spec(source, overrides, size, duration, dt, integrator, base_dir, name):
    """The scene read and checked as `masse run` reads it (SceneError otherwise); nothing is built yet."""
    flags = (_settings(overrides), _flag(size, "size"), _flag(duration, "duration"), _flag(dt, "dt"),
             _flag(integrator, "integrator"))
    if isinstance(source, dict):
        return _masse._spec_from_document(_json(source), os.fspath(base_dir) if base_dir is not None else ".",
                                          name, *flags)
    if isinstance(source, (str, os.PathLike)):
        return _masse._spec_from_file(os.fspath(source), *flags)
    raise TypeError("a scene is a file path or a dict of the scene file's keys (got %s)" % type(source).__name__)


def _masses(masses, what):
    if masses is None:
        return []
    if isinstance(masses, (int, np.integer)) and not isinstance(masses, bool):
        return [int(masses)]
    result = []
    for m in np.asarray(masses).ravel().tolist():
        if isinstance(m, bool) or not isinstance(m, int):
            raise TypeError("%s: mass indices are whole numbers (got %r)" % (what, m))
        result.append(m)
    return result


def _point(value, what):
    point = np.asarray(value, dtype=float)
    if point.shape != (3,):
        raise ValueError("%s: expected a point (x, y, z) (got shape %s)" % (what, point.shape))
    return point.tolist()


class Scene(_masse._Scene):
    """A built scene: the sheet, its obstacles, heat, contact and script, stepped in C++.

    State (see docs/python.md for views and copies): ``positions``, ``velocities`` (N x 3 float64, m and m/s),
    ``pinned`` (bool), ``masses`` (kg), ``thickness`` (m, None without a material), ``rest_positions``, ``coords``
    (layer, row, column per mass) and ``springs`` (M x 2 mass indices) are read-only views of the engine's memory;
    ``temperature`` (C, None without heat), ``events`` and ``summary()`` are copies.
    """

    @classmethod
    def load(cls, source, overrides=None, *, size=None, duration=None, dt=None, integrator=None, base_dir=None,
             name="scene"):
        """Reads a scene file (or a dict of its keys) as `masse run` does, with ``overrides`` set as by ``--set``
        and ``size``, ``duration``, ``dt``, ``integrator`` as by the flags of those names. Bad input raises
        SceneError with the command's message. A dict's relative file paths are relative to ``base_dir`` (default:
        the working folder), and ``name`` stands for its file name in messages."""
        return cls(_spec(source, overrides, size, duration, dt, integrator, base_dir, name))

    def __repr__(self):
        return "<masse.Scene %s %s at t = %g s>" % (self.name, "x".join(map(str, self.size)), self.time)

    def state_hash_text(self):
        """The state hash as `masse run` prints it ("0x" and 16 hex digits)."""
        return "0x%016x" % self.state_hash()

    def spring_strain(self):
        """Engineering strain of every spring against the sheet's rest shape, |x_b - x_a| / |X_b - X_a| - 1 (a new
        array; the springs' ends are ``springs``)."""
        ends = self.springs
        x, rest = self.positions, self.rest_positions
        now = np.linalg.norm(x[ends[:, 1]] - x[ends[:, 0]], axis=1)
        before = np.linalg.norm(rest[ends[:, 1]] - rest[ends[:, 0]], axis=1)
        return now / before - 1.0

    # Scripted actions. Each is a scene file's script action at the scene's current time: it fires at the start of
    # the next step, as the same action in the file would, and shows in ``events`` from then on.

    def act(self, action):
        """Adds a script action written as in a scene file's "script" list, e.g. ``{"action": "gravity", "value":
        [0, -9.8, 0]}``; its "time" defaults to now and may not be in the past. Checked as a file's action is
        (SceneError), its masses first (IndexError)."""
        if not isinstance(action, dict):
            raise TypeError("act: expected a dict such as {'action': 'gravity', 'value': [0, -9.8, 0]} (got %s)"
                            % type(action).__name__)
        action = dict(action)
        action.setdefault("time", self.time)
        self._act(_json(action))

    def grab(self, mass=None, target=None, *, near=None, path=None, label=None, stiffness=None, damping=None,
             max_force=None):
        """Pulls a mass (by index, or the one nearest ``near``) toward ``target`` with a spring, or along ``path``,
        a list of (time, (x, y, z)) keys at absolute times from now on. Stiffness (N/m), damping (N s/m) and the
        pull's cap (N) default as in scene files. Returns the grab's label, for move_grab and release."""
        if (mass is None) == (near is None):
            raise TypeError("grab: give either a mass index or near=(x, y, z)")
        if (target is None) == (path is None):
            raise TypeError("grab: give either a target (x, y, z) or a path of (time, (x, y, z)) keys")
        action = {"action": "grab", "time": self.time}
        if mass is not None:
            (index,) = _masses(mass, "grab")
            self._require_mass(index, "grab")
            action["mass"] = index
        else:
            action["near"] = _point(near, "grab: near")
        if target is not None:
            action["path"] = [{"time": self.time, "position": _point(target, "grab: target")}]
        else:
            action["path"] = [{"time": t, "position": _point(p, "grab: path")} for t, p in path]
        if label is None:
            self._grabs = getattr(self, "_grabs", 0) + 1
            label = "grab %d" % self._grabs
        action["label"] = label
        for key, value in (("stiffness", stiffness), ("damping", damping), ("max_force", max_force)):
            if value is not None:
                action[key] = value
        self._act(_json(action))
        return label

    def move_grab(self, label, target, duration=0.0):
        """Moves a grab's target from where it is now straight to ``target``, reached ``duration`` seconds later
        (at once for 0), then holds it there."""
        self._redirect_grab(label, _point(target, "move_grab: target"), float(duration))

    def release(self, label):
        """Removes a grab's spring."""
        self._act(_json({"action": "release", "grab": label, "time": self.time}))

    def pin(self, masses=None, *, corners=None, edges=None):
        """Pins masses (an index or indices; ``corners`` 0 to 3 of the bottom layer; ``edges`` "x_min", "x_max",
        "z_min", "z_max"): they keep their place and have zero velocity."""
        self._pins("pin", masses, corners, edges)

    def unpin(self, masses=None, *, corners=None, edges=None):
        """Frees pinned masses (named as for pin)."""
        self._pins("unpin", masses, corners, edges)

    def _pins(self, kind, masses, corners, edges):
        indices = _masses(masses, kind)
        for m in indices:
            self._require_mass(m, kind)
        pins = {"masses": indices}
        if corners is not None:
            pins["corners"] = list(corners)
        if edges is not None:
            pins["edges"] = [edges] if isinstance(edges, str) else list(edges)
        self._act(_json({"action": kind, "masses": pins, "time": self.time}))

    def set_gravity(self, gravity):
        """Sets gravity (m/s^2, a vector)."""
        self._act(_json({"action": "gravity", "value": _point(gravity, "set_gravity"), "time": self.time}))

    def set_heater(self, heater, on=True, power=None):
        """Switches a heater (its name, or its index in ``heaters``) on or off; ``power`` (W) is its power from now
        on (its own when left out)."""
        if isinstance(heater, (int, np.integer)) and not isinstance(heater, bool):
            names = self.heaters
            if not 0 <= heater < len(names):
                raise IndexError("set_heater: heater %d does not exist (the scene has %d)" % (heater, len(names)))
            heater = names[heater]
        action = {"action": "heater", "heater": heater, "on": bool(on), "time": self.time}
        if power is not None:
            action["power"] = power
        self._act(_json(action))

    def set_ambient(self, temperature_c):
        """Sets the room air's temperature (C)."""
        self._act(_json({"action": "ambient", "temperature_c": temperature_c, "time": self.time}))

    def set_pressure(self, pressure, ramp=0.0):
        """The forming pressure (Pa) from what it is now to ``pressure`` over ``ramp`` seconds, then held; the rest of
        the scene's schedule is dropped (forming scenes)."""
        self._act(_json({"action": "pressure", "pressure": pressure, "ramp": ramp, "time": self.time}))

    def steer(self, obstacle, to, speed):
        """A kinematic obstacle (a plug) from where it is straight to ``to`` (m) at ``speed`` (m/s), then held; the
        rest of its path is dropped."""
        self._act(_json({"action": "steer", "obstacle": obstacle, "to": _point(to, "steer"), "speed": speed,
                         "time": self.time}))

    def set_obstacle_temperature(self, obstacle, temperature_c):
        """An obstacle's temperature (C) for contact heat, a mould's or a plug's (heat scenes)."""
        self._act(_json({"action": "obstacle_temperature", "obstacle": obstacle, "temperature_c": temperature_c,
                         "time": self.time}))


def run(scene, out=None, *, overrides=None, size=None, duration=None, dt=None, integrator=None, force=False,
        frames_every=None, formats=None, progress=False, base_dir=None, name="scene", **settings):
    """Does what ``masse run SCENE --out OUT`` does and returns summary.json as a dict.

    ``overrides`` (and any further keyword arguments, ``**{"heat.heaters[0].power": 8000}``) set scene keys as
    ``--set`` does; ``size``, ``duration``, ``dt``, ``integrator``, ``force``, ``frames_every`` and ``formats`` are the
    command's flags. The same files are written, under the same folder rules (a folder holding a run is refused
    without ``force``; the folder appears only when the run has finished). Without ``out`` nothing is written. Bad
    input raises SceneError before anything is written; a run that goes wrong raises SimulationError. The command's
    warnings are issued as Python warnings."""
    merged = dict(overrides or {})
    merged.update(settings)
    spec = _spec(scene, merged, size, duration, dt, integrator, base_dir, name)
    if isinstance(formats, str):
        formats = formats.split(",")
    summary, printed = _masse._run(spec, os.fspath(out) if out is not None else "", bool(force),
                                   None if frames_every is None else int(frames_every), list(formats or []),
                                   bool(progress))
    for line in printed.splitlines():
        if line.strip():
            warnings.warn(line[len("warning: "):] if line.startswith("warning: ") else line, stacklevel=2)
    return summary


def executable():
    """The ``masse`` command this module runs for sweep: $MASSE_EXECUTABLE, else the one built or installed with
    the module, else the first on the PATH."""
    found = os.environ.get("MASSE_EXECUTABLE")
    if found:
        return found
    try:
        from ._config import MASSE_EXECUTABLE
        if os.access(MASSE_EXECUTABLE, os.X_OK):
            return MASSE_EXECUTABLE
    except ImportError:
        pass
    found = shutil.which("masse")
    if found:
        return found
    raise FileNotFoundError("the masse command was not found: build it (or install it with cmake --install), put "
                            "it on the PATH, or set MASSE_EXECUTABLE")


def collect(folder):
    """A study folder's results, as ``masse sweep --collect`` reads them: the parameters and outputs (names and
    units), and per case its number, status ("done", "failed", "not run"), exit code, message, varied values and
    collected outputs (None where a case has no such value)."""
    return _masse._collect(os.fspath(folder))


def sweep(study, out, *, jobs=1, threads=1, retry_failed=False, slurm=False, partition=None, time=None,
          cpus_per_task=None, throttle=None, wait=False, plots=True, echo=False):
    """Runs ``masse sweep STUDY --out OUT`` (the same study machinery, workers and Slurm job array) and returns
    collect(out). Bad input raises SceneError with the command's message, nothing written; a case that fails is
    reported in its results (status "failed" and its message). ``echo`` shows the command's output."""
    command = [executable(), "sweep", os.fspath(study), "--out", os.fspath(out), "--threads", str(int(threads))]
    if slurm:
        command.append("--slurm")
    else:
        command += ["--jobs", str(int(jobs))]
    for flag, value in (("--partition", partition), ("--time", time), ("--cpus-per-task", cpus_per_task),
                        ("--throttle", throttle)):
        if value is not None:
            command += [flag, str(value)]
    for flag, on in (("--retry-failed", retry_failed), ("--wait", wait), ("--no-plots", not plots)):
        if on:
            command.append(flag)
    done = subprocess.run(command, capture_output=True, text=True)
    if echo:
        print(done.stdout, end="")
        print(done.stderr, end="")
    messages = [line[len("masse: "):] for line in done.stderr.splitlines() if line.startswith("masse: ")]
    if done.returncode == 2:
        raise SceneError(messages[-1] if messages else done.stderr.strip())
    failure = "masse sweep failed (exit code %d): %s" % (done.returncode, done.stderr.strip())
    try:
        results = collect(out)
    except SceneError:
        raise RuntimeError(failure) from None
    # Exit code 1 with failed cases is a study that ran: its results say which cases failed and why.
    if done.returncode != 0 and results["failed"] == 0:
        raise RuntimeError(failure)
    return results
