"""Bad input raises with the command's own message and writes nothing; a bad mass index raises IndexError."""

import os

import numpy as np
import pytest

import masse
from conftest import SCENES, command_message

DRAPE = SCENES / "drape-forming.json"
DRAG = SCENES / "drag.json"

# (overrides for Python, the same as --set arguments for the command)
BAD_SETTINGS = [
    pytest.param({"heat.heaters[0].powr": 8000}, ["heat.heaters[0].powr=8000"], id="wrong key"),
    pytest.param({"heat.heaters[0].power": "hot"}, ["heat.heaters[0].power=hot"], id="wrong type"),
    pytest.param({"heat.heaters[0].power": "8000"}, ['heat.heaters[0].power="8000"'], id="number as text"),
    pytest.param({"heat.heaters[0].on": 1}, ["heat.heaters[0].on=1"], id="number for a flag"),
    pytest.param({"contact.friction": -1}, ["contact.friction=-1"], id="out of range"),
    pytest.param({"heat.heaters[3].power": 1}, ["heat.heaters[3].power=1"], id="missing list element"),
    pytest.param({"integrator.dt": float("nan")}, ["integrator.dt=nan"], id="not a number"),
    pytest.param({"sheet.size": [8, 2, 8]}, ["sheet.size=[8,2,8]"], id="list for text"),
]


@pytest.mark.parametrize("overrides,settings", BAD_SETTINGS)
def test_bad_settings_raise_the_commands_message(tmp_path, overrides, settings):
    expected = command_message("run", DRAPE, *[a for s in settings for a in ("--set", s)], "--out", tmp_path / "cmd")
    with pytest.raises(masse.SceneError) as error:
        masse.Scene.load(DRAPE, overrides)
    assert str(error.value) == expected
    with pytest.raises(masse.SceneError) as error:
        masse.run(DRAPE, out=tmp_path / "py", overrides=overrides)
    assert str(error.value) == expected
    assert os.listdir(tmp_path) == []  # neither wrote anything, not even a staging folder


@pytest.mark.parametrize("keyword,flag,value", [
    ("size", "--size", "8x8"),
    ("size", "--size", "1x2x1"),
    ("duration", "--duration", "-1"),
    ("dt", "--dt", "5"),
    ("integrator", "--integrator", "leapfrog"),
])
def test_bad_flags_raise_the_commands_message(tmp_path, keyword, flag, value):
    expected = command_message("run", DRAPE, flag, value, "--out", tmp_path / "cmd")
    with pytest.raises(masse.SceneError) as error:
        masse.Scene.load(DRAPE, **{keyword: value})
    assert str(error.value) == expected
    with pytest.raises(masse.SceneError) as error:
        masse.run(DRAPE, out=tmp_path / "py", **{keyword: value})
    assert str(error.value) == expected
    assert os.listdir(tmp_path) == []


def test_missing_file(tmp_path):
    missing = tmp_path / "no-such-scene.json"
    expected = command_message("run", missing, "--out", tmp_path / "cmd")
    with pytest.raises(masse.SceneError) as error:
        masse.Scene.load(missing)
    assert str(error.value) == expected
    with pytest.raises(masse.SceneError) as error:
        masse.run(missing, out=tmp_path / "py")
    assert str(error.value) == expected
    assert os.listdir(tmp_path) == []


def test_bad_scene_file(tmp_path):
    bad = tmp_path / "bad.json"
    bad.write_text('{"sheet": {"size": "8x2x8", "stifness": 3}}')
    expected = command_message("run", bad)
    with pytest.raises(masse.SceneError) as error:
        masse.Scene.load(bad)
    assert str(error.value) == expected
    assert "did you mean 'stiffness'" in expected


def test_scene_error_is_a_value_error():
    assert issubclass(masse.SceneError, ValueError)
    assert issubclass(masse.SimulationError, RuntimeError)


def test_wrong_python_types():
    with pytest.raises(TypeError):
        masse.Scene.load(42)
    with pytest.raises(TypeError):
        masse.Scene.load(DRAG, ["contact.friction=1"])
    with pytest.raises(TypeError):
        masse.Scene.load(DRAG, {1: 2})
    with pytest.raises(TypeError):
        masse.Scene.load(DRAG, size=object())


def test_bad_study_raises_the_commands_message(tmp_path):
    study = tmp_path / "study.json"
    study.write_text('{"scene": "%s", "vary": [{"key": "contact.friction", "values": [-1]}], '
                     '"outputs": ["sim_seconds"]}' % DRAG)
    expected = command_message("sweep", study, "--out", tmp_path / "cmd")
    with pytest.raises(masse.SceneError) as error:
        masse.sweep(study, tmp_path / "py")
    assert str(error.value) == expected
    assert sorted(os.listdir(tmp_path)) == ["study.json"]


def test_bad_mass_indices_raise_index_error():
    scene = masse.Scene.load(DRAG, {"script": []})
    n = scene.mass_count
    for bad in (n, -1, 10**12):
        with pytest.raises(IndexError, match="does not exist"):
            scene.grab(bad, (0, 0, 0))
        with pytest.raises(IndexError):
            scene.pin(bad)
        with pytest.raises(IndexError):
            scene.unpin([0, bad])
    with pytest.raises(IndexError):
        scene.act({"action": "grab", "mass": n, "path": [{"position": [0, 0, 0]}]})
    with pytest.raises(IndexError):
        scene.act({"action": "pin", "masses": {"masses": [n]}})
    with pytest.raises(IndexError):
        scene.index(-1, 0, 0)
    with pytest.raises(IndexError):
        scene.index(2, 0, 0)
    with pytest.raises(IndexError):
        scene.index(1, 7, 0)  # the top layer is one row and column smaller
    scene.step()
    assert not scene.pinned.any()  # nothing was added


def test_bad_actions_raise_scene_errors():
    scene = masse.Scene.load(DRAPE, size="6x2x6", duration=1.0)
    scene.step(2)
    with pytest.raises(masse.SceneError, match="action.heater: no heater is named 'grill'"):
        scene.set_heater("grill")
    with pytest.raises(IndexError):
        scene.set_heater(1)
    with pytest.raises(masse.SceneError, match="action.grab: no earlier grab is labelled 'nobody'"):
        scene.release("nobody")
    with pytest.raises(masse.SceneError, match="grab: no grab is labelled 'nobody'"):
        scene.move_grab("nobody", (0, 0, 0))
    with pytest.raises(masse.SceneError, match="action.time: must be at or after the scene's time"):
        scene.act({"action": "gravity", "value": [0, 0, 0], "time": 0.0})
    with pytest.raises(masse.SceneError, match="action.obstacle: no obstacle is named 'wall'"):
        scene.act({"action": "move", "obstacle": "wall", "path": [{"time": 1, "position": [0, 0, 0]}]})
    with pytest.raises(masse.SceneError, match="action.stifness: unknown key"):
        scene.act({"action": "grab", "mass": 0, "stifness": 3, "path": [{"position": [0, 0, 0]}]})
    with pytest.raises(masse.SceneError, match="action.stiffness"):
        scene.grab(0, (0, 0, 0), stiffness=-1)
    with pytest.raises(ValueError):
        scene.set_gravity((0, 1))
    with pytest.raises(masse.SceneError):
        scene.set_gravity((0, float("nan"), 0))
    with pytest.raises(masse.SceneError, match="action.action"):
        masse.Scene.load(DRAG).set_ambient(30)  # no heat section
    scene.step()
    assert [e["name"] for e in scene.events] == []


def test_nothing_crashes_on_odd_but_valid_calls():
    scene = masse.Scene.load(DRAG, {"script": []})
    scene.set_positions(scene.positions)  # its own view, read while written
    scene.set_velocities(np.zeros((scene.mass_count, 3), dtype=np.float32))
    scene.set_positions(np.asfortranarray(scene.positions.copy()))
    label = scene.grab(0, (0, 0, 0))
    scene.move_grab(label, (0, 1, 0))  # before it has fired
    scene.release(label)
    scene.release(label)  # a second release of the same grab does nothing
    scene.step(3)
    assert np.all(np.isfinite(scene.positions))
