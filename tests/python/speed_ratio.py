"""The cost of stepping a scene from Python against `masse run` of the same scene: the ratio of wall times, the
median of ROUNDS rounds, each round running the command and then the module, at the same thread count. Not a test
(its figure depends on the machine's load); docs/python.md gives its output.

    PYTHONPATH=build/python /usr/bin/python3 tests/python/speed_ratio.py [SIZE] [DURATION] [THREADS] [ROUNDS]

Two ratios: stepping alone (the module's Scene.run() against the stepping time summary.json reports), and the whole
(a Python process that imports the module, reads, builds and runs the scene, against the whole command).
"""

import json
import os
import pathlib
import statistics
import subprocess
import sys
import tempfile
import time

import masse

SCENE = pathlib.Path(__file__).resolve().parents[2] / "data" / "scenes" / "paper-drop.json"
PYTHON_RUN = """
import sys, time
start = time.perf_counter()
import masse
masse.set_threads(int(sys.argv[4]))
scene = masse.Scene.load(sys.argv[1], size=sys.argv[2], duration=sys.argv[3])
before = time.perf_counter()
scene.run()
after = time.perf_counter()
print(after - before, after - start, scene.state_hash_text())
"""


def main(size="128x2x128", duration="1", threads="2", rounds=3):
    stepping, whole = [], []
    with tempfile.TemporaryDirectory() as work:
        for k in range(int(rounds)):
            out = os.path.join(work, "run%d" % k)
            start = time.perf_counter()
            subprocess.run([masse.executable(), "run", str(SCENE), "--size", size, "--duration", duration,
                            "--threads", threads, "--quiet", "--out", out], check=True, stdout=subprocess.DEVNULL)
            command_whole = time.perf_counter() - start
            summary = json.loads(pathlib.Path(out, "summary.json").read_text())
            done = subprocess.run([sys.executable, "-c", PYTHON_RUN, str(SCENE), size, duration, threads],
                                  check=True, capture_output=True, text=True)
            python_stepping, python_whole, state = done.stdout.split()
            assert state == summary["final"]["state_hash"], "the module and the command disagree"
            stepping.append(float(python_stepping) / summary["wall_seconds"])
            whole.append(float(python_whole) / command_whole)
            print("round %d: stepping %.2f s (module) / %.2f s (command) = %.3f; whole %.2f s / %.2f s = %.3f"
                  % (k + 1, float(python_stepping), summary["wall_seconds"], stepping[-1], float(python_whole),
                     command_whole, whole[-1]))
    print("median of %d rounds, %s sheet, %s s simulated, %s thread(s): stepping %.3f, whole %.3f (module / command)"
          % (int(rounds), size, duration, threads, statistics.median(stepping), statistics.median(whole)))


if __name__ == "__main__":
    main(*sys.argv[1:])
