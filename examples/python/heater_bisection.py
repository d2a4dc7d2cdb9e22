"""Bisection for the heater power: the highest panel power (within 100 W) at which drape forming still keeps the
thinnest wall above a limit. A hotter sheet is softer and thins more where it is drawn over the mould, so the
thinnest wall falls as the power rises; each trial is one run of the scene, stepped in C++.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/heater_bisection.py [LIMIT]
"""

import os
import sys

import masse

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(HERE, "..", "..", "data", "scenes", "drape-forming.json")


def thinnest_wall(power, size):
    """The thinnest wall at the end of the scene, as a fraction of the sheet's thickness."""
    scene = masse.Scene.load(SCENE, {"heat.heaters[0].power": power}, size=size)
    scene.run()
    return scene.summary()["final"]["thickness"]["min_ratio"]


def highest_power(limit, low=2000.0, high=16000.0, tolerance=100.0, size="6x2x6"):
    """Bisects [low, high] W: `low` must keep the wall above `limit`, `high` must not."""
    at_low, at_high = thinnest_wall(low, size), thinnest_wall(high, size)
    print("%8.0f W: thinnest wall %.3f" % (low, at_low))
    print("%8.0f W: thinnest wall %.3f" % (high, at_high))
    if not at_low >= limit > at_high:
        raise SystemExit("the limit %.3f is not between the walls at %g W and %g W" % (limit, low, high))
    while high - low > tolerance:
        middle = 0.5 * (low + high)
        wall = thinnest_wall(middle, size)
        print("%8.0f W: thinnest wall %.3f" % (middle, wall))
        if wall >= limit:
            low = middle
        else:
            high = middle
    return low


if __name__ == "__main__":
    limit = float(sys.argv[1]) if len(sys.argv) > 1 else 0.6
    power = highest_power(limit)
    print("highest power keeping the thinnest wall above %.0f%%: %.0f W" % (100 * limit, power))
