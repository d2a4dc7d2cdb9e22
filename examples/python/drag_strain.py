"""Dragging a mass and reading the sheet's strain: the drag scene's sheet lies on a table; a spring picks up one
corner, lifts it and carries it sideways in small moves, and after each move the script reads the positions (a view
of the engine's memory, no copy) and every spring's strain.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/drag_strain.py [OUT.csv]
"""

import os
import sys

import numpy as np

import masse

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(HERE, "..", "..", "data", "scenes", "drag.json")


def main(csv=None):
    # The scene without its own script: this program does the dragging.
    scene = masse.Scene.load(SCENE, {"script": [], "run.stop_at_rest": False})
    nx, layers, nz = scene.size
    corner = scene.index(0, nz - 1, nx - 1)
    x = scene.positions  # a read-only view: it follows the simulation
    start = x[corner].copy()
    hand = scene.grab(corner, start, stiffness=20, damping=0.05, max_force=2.0)
    rows = []
    print("%6s %10s %10s %12s %12s" % ("t s", "corner y", "corner x", "max strain", "mean |strain|"))
    for k in range(1, 21):
        # Up 0.5 m over the first ten moves, then 0.4 m along x; each move takes 0.15 s.
        lift = min(k, 10) / 10 * 0.5
        along = max(k - 10, 0) / 10 * 0.4
        scene.move_grab(hand, start + [along, lift, 0], duration=0.15)
        scene.run(until=scene.time + 0.15)
        strain = scene.spring_strain()
        rows.append((scene.time, x[corner, 1], x[corner, 0], strain.max(), np.abs(strain).mean()))
        print("%6.2f %10.3f %10.3f %12.4f %12.4f" % rows[-1])
    scene.release(hand)
    scene.run(until=scene.time + 1.0)
    print("released at %.2f s; the corner fell back to y = %.3f m" % (rows[-1][0], x[corner, 1]))
    if csv:
        np.savetxt(csv, np.array(rows), delimiter=",", header="time_s,corner_y_m,corner_x_m,max_strain,"
                   "mean_abs_strain", comments="")
    return rows


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else None)
