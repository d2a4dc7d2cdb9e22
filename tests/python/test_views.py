"""The state arrays: views of the engine's memory (no copy, read-only, kept alive by their base) where the docs say
so, copies where they say so."""

import gc

import numpy as np
import pytest

import masse
from conftest import SCENES

DRAPE = SCENES / "drape-forming.json"

VIEWS = ["positions", "velocities", "pinned", "masses", "thickness", "rest_positions", "coords", "springs"]


@pytest.fixture
def scene():
    return masse.Scene.load(DRAPE, size="6x2x6", duration=1.0)


@pytest.mark.parametrize("name", VIEWS)
def test_views_share_the_engines_memory_and_are_read_only(scene, name):
    a = getattr(scene, name)
    b = getattr(scene, name)
    assert np.shares_memory(a, b)  # two reads, one memory: the engine's
    assert not a.flags.owndata
    assert a.base is scene
    assert not a.flags.writeable
    with pytest.raises(ValueError):
        a[0] = 0
    with pytest.raises(ValueError):
        a.flags.writeable = True


def test_shapes_and_types(scene):
    n = scene.mass_count
    assert scene.positions.shape == (n, 3) and scene.positions.dtype == np.float64
    assert scene.positions.strides == (24, 8)
    assert scene.velocities.shape == (n, 3)
    assert scene.pinned.shape == (n,) and scene.pinned.dtype == np.bool_
    assert scene.thickness.shape == (n,) and scene.thickness.dtype == np.float64
    assert scene.coords.dtype == np.int32
    assert scene.springs.shape[1] == 2 and scene.springs.dtype == np.uint32
    assert scene.springs.max() < n


def test_a_view_follows_the_simulation(scene):
    x = scene.positions
    v = scene.velocities
    t = scene.thickness
    before = x.copy()
    scene.run(until=0.5)
    assert not np.array_equal(x, before)  # the same memory, stepped
    np.testing.assert_array_equal(x, scene.positions)
    np.testing.assert_array_equal(v, scene.velocities)
    np.testing.assert_array_equal(t, scene.thickness)


def test_a_view_keeps_its_scene_alive():
    x = masse.Scene.load(DRAPE, size="6x2x6").positions
    gc.collect()
    assert isinstance(x.base, masse.Scene)
    assert np.all(np.isfinite(x)) and x.shape[1] == 3
    x.base.step()
    assert np.all(np.isfinite(x))


def test_copies_are_copies(scene):
    scene.step(3)
    temperature = scene.temperature
    assert temperature.flags.owndata and temperature.flags.writeable
    assert not np.shares_memory(temperature, scene.temperature)
    temperature[:] = 0
    assert scene.temperature.min() > 0
    events = scene.events
    events.append({"name": "mine"})
    assert scene.events != events
    summary = scene.summary()
    summary["final"] = None
    assert scene.summary()["final"] is not None


def test_set_positions_copies_in(scene):
    x = scene.positions.copy()
    scene.set_positions(x)
    x[:] = 0
    assert not np.array_equal(scene.positions, x)
