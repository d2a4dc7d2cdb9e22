"""The Scene API: loading, stepping, state, events, summaries, scripted actions, threads, runs and studies."""

import json
import threading

import numpy as np
import pytest

import masse
from conftest import SCENES, SOURCE, run_command

DRAG = SCENES / "drag.json"
DRAPE = SCENES / "drape-forming.json"


def small_drape(**kwargs):
    return masse.Scene.load(DRAPE, size="6x2x6", duration=1.0, **kwargs)


def test_load_and_step():
    scene = masse.Scene.load(DRAG)
    assert scene.name == "drag"
    assert scene.size == (8, 2, 8)
    assert scene.mass_count == 8 * 8 + 7 * 7
    assert scene.time == 0 and scene.steps == 0
    scene.step()
    scene.step(4)
    assert scene.steps == 5
    assert scene.time == pytest.approx(5 * scene.dt)
    scene.step(0)
    assert scene.steps == 5
    with pytest.raises(ValueError):
        scene.step(-1)
    assert "drag" in repr(scene)


def test_overrides_and_flags_change_the_scene():
    scene = masse.Scene.load(DRAPE, {"heat.heaters[0].power": 8000, "integrator.dt": 0.02}, size=(6, 2, 6),
                             duration=0.5)
    assert scene.size == (6, 2, 6)
    assert scene.dt == 0.02
    assert scene.duration == 0.5
    assert scene.summary()["dt"] == 0.02
    assert scene.heaters == ["panel"]


def test_load_from_a_dict():
    document = json.loads(DRAG.read_text())
    document["run"] = {"duration": 0.3, "stop_at_rest": False}
    scene = masse.Scene.load(document, base_dir=SCENES)
    scene.run()
    assert scene.time == pytest.approx(0.3)
    from_file = masse.Scene.load(DRAG, duration=0.3)
    from_file.run()
    assert scene.state_hash() == from_file.state_hash()


def test_run_stops_at_the_scenes_end_or_at_until():
    scene = small_drape()
    scene.run(until=0.3)
    assert scene.time == pytest.approx(0.3)
    assert not scene.finished
    scene.run()
    assert scene.finished
    assert scene.time == pytest.approx(1.0)
    with pytest.raises(ValueError):
        scene.run(until=float("nan"))


def test_state_hash_and_summary_agree():
    scene = masse.Scene.load(DRAG, duration=0.3)
    scene.run()
    summary = scene.summary()
    assert summary["final"]["state_hash"] == scene.state_hash_text()
    assert summary["steps"] == scene.steps
    assert isinstance(scene.state_hash(), int)


def test_events_are_dicts():
    scene = masse.Scene.load(DRAG)
    scene.run(until=0.6)
    events = scene.events
    assert [e["name"] for e in events] == ["contact", "grab"]
    assert all(set(e) == {"name", "object", "sim_time", "wall_time"} for e in events)
    assert events[0]["object"] == "table"
    assert events[1]["object"] == "hand"
    assert events[1]["sim_time"] == pytest.approx(0.3)


def test_material_state():
    scene = small_drape()
    scene.run(until=0.3)
    assert scene.temperature.shape == (scene.mass_count,)
    assert scene.temperature.min() >= 19.9  # C, from 20 C under a heater
    assert scene.thickness.shape == (scene.mass_count,)
    assert scene.thickness.max() == pytest.approx(0.002, rel=0.2)
    plain = masse.Scene.load(DRAG)
    assert plain.temperature is None
    assert plain.thickness is None


def test_set_positions_and_velocities():
    scene = masse.Scene.load(DRAG)
    x = scene.positions.copy()
    x[:, 1] += 0.05
    scene.set_positions(x)
    np.testing.assert_array_equal(scene.positions, x)
    v = np.zeros((scene.mass_count, 3))
    v[:, 0] = 0.1
    scene.set_velocities(v)
    np.testing.assert_array_equal(scene.velocities, v)
    scene.step()
    assert np.all(np.isfinite(scene.positions))


def test_set_velocities_keeps_pinned_masses_still():
    scene = small_drape()
    pinned = scene.pinned.copy()
    assert pinned.any() and not pinned.all()
    scene.set_velocities(np.ones((scene.mass_count, 3)))
    assert np.all(scene.velocities[pinned] == 0)
    assert np.all(scene.velocities[~pinned] == 1)


def test_set_state_refuses_bad_arrays():
    scene = masse.Scene.load(DRAG)
    before = scene.positions.copy()
    n = scene.mass_count
    for bad in (np.zeros((n, 2)), np.zeros((n + 1, 3)), np.zeros(3 * n)):
        with pytest.raises(ValueError, match=r"expected an array of shape \(%d, 3\)" % n):
            scene.set_positions(bad)
    x = before.copy()
    x[7, 2] = np.nan
    with pytest.raises(ValueError, match="mass 7 has a value that is not finite"):
        scene.set_positions(x)
    v = np.zeros((n, 3))
    v[3, 0] = np.inf
    with pytest.raises(ValueError, match="mass 3"):
        scene.set_velocities(v)
    with pytest.raises((ValueError, TypeError)):
        scene.set_positions("not an array")
    np.testing.assert_array_equal(scene.positions, before)


def test_grab_drag_and_release():
    scene = masse.Scene.load(DRAG, {"script": []})
    corner = scene.index(0, 7, 7)
    start = scene.positions[corner].copy()
    label = scene.grab(corner, start, stiffness=20, max_force=2.0)
    assert label == "grab 1"
    scene.step()
    assert "grab" in [e["name"] for e in scene.events]
    scene.move_grab(label, start + [0, 0.3, 0], duration=0.5)
    scene.run(until=1.5)
    assert scene.positions[corner, 1] > start[1] + 0.2
    scene.release(label)
    scene.step()
    assert "release" in [e["name"] for e in scene.events]


def test_grab_near_a_point_and_along_a_path():
    scene = masse.Scene.load(DRAG, {"script": []})
    t = scene.time
    label = scene.grab(near=(0.5, -0.49, 0.5), path=[(t, (0.5, -0.49, 0.5)), (t + 1, (0.5, 0.0, 0.5))],
                       label="hand", stiffness=20, max_force=2.0)
    assert label == "hand"
    scene.run(until=1.2)
    assert scene.positions[:, 1].max() > -0.2


def test_pin_unpin_and_gravity():
    scene = masse.Scene.load(DRAG, {"script": []})
    scene.pin([0, 1, 2])
    assert not scene.pinned[:3].any()  # an action fires at the start of the next step
    scene.step()
    assert scene.pinned[:3].all() and not scene.pinned[3:].any()
    scene.unpin(1)
    scene.pin(corners=[3])
    scene.set_gravity((0, 0, 0))
    scene.step()
    assert list(scene.pinned[:3]) == [True, False, True]
    assert scene.pinned.sum() == 3
    assert [e["name"] for e in scene.events if e["name"] != "contact"][-3:] == ["unpin", "pin", "gravity"]


def test_heater_and_ambient():
    scene = small_drape()
    scene.set_heater("panel", False)
    scene.set_ambient(25.0)
    scene.step()
    names = [(e["name"], e["object"]) for e in scene.events]
    assert ("heater off", "panel") in names and ("ambient", "air") in names
    scene.set_heater(0, True)
    scene.step()
    assert [e["name"] for e in scene.events][-1] == "heater on"


def test_process_actions():
    scene = masse.Scene.load(SCENES / "plug-assist-cup.json", size="8x2x8", duration=0.5)
    scene.set_pressure(20000.0, ramp=0.1)
    scene.steer("plug", [0, 0.0, 0], 0.1)
    scene.set_obstacle_temperature("mould", 75.0)
    scene.step()
    names = [(e["name"], e["object"]) for e in scene.events]
    assert ("pressure", "sheet") in names and ("steer", "plug") in names
    assert ("obstacle temperature", "mould") in names
    with pytest.raises(masse.SceneError, match="static"):
        scene.steer("mould", [0, 0, 0], 0.1)


def test_act_takes_a_scene_files_action():
    scene = masse.Scene.load(DRAG, {"script": []})
    scene.act({"action": "gravity", "value": [0, 0, 0], "time": 0.09})
    scene.step(3)
    assert [e for e in scene.events if e["name"] == "gravity"] == []
    scene.step()
    (gravity,) = [e for e in scene.events if e["name"] == "gravity"]
    assert gravity["sim_time"] == pytest.approx(0.09)


def test_python_actions_give_the_same_bits_as_the_files_script():
    """The drag scene's script (grab at 0.3 s along a path, release at 3 s) given from Python between steps."""
    from_file = masse.Scene.load(DRAG)
    from_file.run()
    script = json.loads(DRAG.read_text())["script"]
    scene = masse.Scene.load(DRAG, {"script": []})
    for action in script:
        scene.run(until=action["time"])
        scene.act(action)
    scene.run()
    assert scene.state_hash() == from_file.state_hash()
    assert [(e["name"], e["object"], e["sim_time"]) for e in scene.events] == \
        [(e["name"], e["object"], e["sim_time"]) for e in from_file.events]


def test_spring_strain():
    scene = masse.Scene.load(DRAG)
    strain = scene.spring_strain()
    assert strain.shape == (len(scene.springs),)
    assert np.abs(strain).max() < 1e-9  # the sheet starts at rest length
    x = scene.positions.copy() * 1.01
    scene.set_positions(x)
    assert scene.spring_strain() == pytest.approx(0.01)


def test_index_and_coords():
    scene = masse.Scene.load(DRAG)
    i = scene.index(1, 2, 3)
    assert list(scene.coords[i]) == [1, 2, 3]
    assert scene.coords.shape == (scene.mass_count, 3)


def test_threads():
    before = masse.threads()
    try:
        masse.set_threads(2)
        assert masse.threads() == 2
        with pytest.raises(masse.SceneError, match="threads: must be a whole number of threads from 1 to 1024"):
            masse.set_threads(0)
    finally:
        masse.set_threads(before)


def test_stepping_releases_the_gil():
    scene = masse.Scene.load(DRAG, {"run.stop_at_rest": False})
    worker = threading.Thread(target=scene.step, args=(400,))
    turns = 0
    worker.start()
    while worker.is_alive():
        turns += 1
    worker.join()
    assert scene.steps == 400
    assert turns > 1000  # this thread ran Python the whole time the other stepped


def test_concurrent_steps_of_one_scene_take_turns():
    scene = masse.Scene.load(DRAG, {"run.stop_at_rest": False})
    workers = [threading.Thread(target=scene.step, args=(50,)) for _ in range(3)]
    for w in workers:
        w.start()
    for w in workers:
        w.join()
    assert scene.steps == 150
    alone = masse.Scene.load(DRAG, {"run.stop_at_rest": False})
    alone.step(150)
    assert scene.state_hash() == alone.state_hash()


def test_run_writes_what_the_command_writes(tmp_path):
    out = tmp_path / "run"
    with pytest.warns(UserWarning, match=r"1 script action\(s\) never fired, the run ended at 1 s: hand"):
        summary = masse.run(DRAG, out=out, duration=1.0, frames_every=10, formats="vtp,obj")
    assert json.loads((out / "summary.json").read_text()) == summary
    assert (out / "events.csv").is_file()
    assert (out / "frames.pvd").is_file()
    assert any((out / "frames").glob("*.obj"))
    command_out = tmp_path / "command"
    code, stdout, stderr = run_command("run", DRAG, "--out", command_out, "--duration", 1.0, "--frames-every", 10,
                                       "--format", "vtp,obj", "--quiet")
    assert code == 0, stderr
    from_command = json.loads((command_out / "summary.json").read_text())
    assert summary["final"]["state_hash"] == from_command["final"]["state_hash"]
    assert sorted(p.name for p in out.iterdir()) == sorted(p.name for p in command_out.iterdir())
    assert sorted(p.name for p in (out / "frames").iterdir()) == sorted(p.name for p in (command_out / "frames").iterdir())


def test_run_overrides_as_keywords_and_without_output():
    summary = masse.run(DRAPE, size="6x2x6", duration=0.3, **{"heat.heaters[0].power": 5000, "script": []})
    assert summary["size"] == "6x2x6"
    assert "thickness" in summary["final"]


def test_run_refuses_a_folder_holding_a_run_unless_forced(tmp_path):
    out = tmp_path / "run"
    masse.run(DRAG, out=out, duration=0.3, overrides={"script": []})
    with pytest.raises(masse.SceneError, match="--force"):
        masse.run(DRAG, out=out, duration=0.3, overrides={"script": []})
    masse.run(DRAG, out=out, duration=0.6, force=True, overrides={"script": []})
    assert json.loads((out / "summary.json").read_text())["sim_seconds"] == pytest.approx(0.6)


def test_sweep_runs_a_study_and_collects_it(tmp_path):
    study = {
        "name": "tiny", "scene": str(DRAG), "set": {"run.duration": 0.3},
        "vary": [{"name": "friction", "key": "contact.friction", "values": [0.2, 0.6]}],
        "outputs": [{"name": "hash", "path": "final.state_hash"}, "sim_seconds"],
    }
    path = tmp_path / "tiny.json"
    path.write_text(json.dumps(study))
    results = masse.sweep(path, tmp_path / "out", jobs=2, plots=False)
    assert results["done"] == 2 and results["failed"] == 0
    assert [c["values"]["friction"] for c in results["cases"]] == [0.2, 0.6]
    assert all(c["outputs"]["sim_seconds"] == pytest.approx(0.3) for c in results["cases"])
    assert (tmp_path / "out" / "results.csv").is_file()
    assert masse.collect(tmp_path / "out") == results
