"""A scene stepped from Python gives the same state hash as `masse run` of the same scene, at any thread count."""

import json

import pytest

import masse
from conftest import SCENES, run_command

CASES = [
    pytest.param(SCENES / "drag.json", [], {}, id="drag, contact and a scripted grab"),
    pytest.param(SCENES / "drape-forming.json", ["--size", "8x2x8", "--duration", "3"], {"size": "8x2x8", "duration": 3},
                 id="drape forming 8x2x8, heat and implicit"),
    pytest.param(SCENES / "paper-drop.json", ["--set", "run.duration=1.5"], {"overrides": {"run.duration": 1.5}},
                 id="paper drop, two obstacles"),
]


def command_hash(scene, args, threads, out):
    code, stdout, stderr = run_command("run", scene, *args, "--threads", threads, "--out", out, "--quiet")
    assert code == 0, stderr
    summary = json.loads((out / "summary.json").read_text())
    assert ("state " + summary["final"]["state_hash"]) in stdout
    return summary["final"]["state_hash"]


@pytest.mark.parametrize("scene,args,keywords", CASES)
def test_python_matches_the_command_at_any_thread_count(tmp_path, scene, args, keywords):
    expected = command_hash(scene, args, 2, tmp_path / "command")
    before = masse.threads()
    try:
        for threads in (1, 2, 3):
            masse.set_threads(threads)
            stepped = masse.Scene.load(scene, **keywords)
            stepped.run()
            assert stepped.state_hash_text() == expected, "%d thread(s)" % threads
        # A Python loop of single steps lands on the same bits as run().
        masse.set_threads(1)
        stepped = masse.Scene.load(scene, **keywords)
        while not stepped.finished:
            stepped.step()
        assert stepped.state_hash_text() == expected
        summary = masse.run(scene, **keywords)
        assert summary["final"]["state_hash"] == expected
    finally:
        masse.set_threads(before)
