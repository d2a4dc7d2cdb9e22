"""The heater-power study: the drape-forming scene over a range of panel powers, run as a parameter study by `masse
sweep` (two cases at a time), and the thinnest wall and the hottest place plotted against the power.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/heater_study.py out/heater-study
"""

import json
import os
import sys

import matplotlib

matplotlib.use("Agg")  # files only: no display needed
import matplotlib.pyplot as plt  # noqa: E402

import masse  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(HERE, "..", "..", "data", "scenes", "drape-forming.json")


def main(out, powers=(4000, 6000, 8000, 10000, 12000, 14000), size="8x2x8"):
    os.makedirs(out, exist_ok=True)
    study = {
        "name": "heater-power",
        "scene": os.path.abspath(SCENE),
        "set": {"sheet.size": size, "output.frames_every": 0},
        "vary": [{"name": "power", "key": "heat.heaters[0].power", "unit": "W", "values": list(powers)}],
        "outputs": [{"name": "thinnest", "path": "final.thickness.min_ratio"},
                    {"name": "hottest", "path": "final.temperature_c.max"}],
    }
    study_file = os.path.join(out, "heater-power.json")
    with open(study_file, "w") as f:
        json.dump(study, f, indent=2)
    # A second run of this script resumes the study folder: finished cases are not run again.
    results = masse.sweep(study_file, os.path.join(out, "study"), jobs=2, plots=False)
    done = [c for c in results["cases"] if c["status"] == "done"]
    power = [c["values"]["power"] for c in done]
    thinnest = [100 * c["outputs"]["thinnest"] for c in done]
    hottest = [c["outputs"]["hottest"] for c in done]

    figure, wall = plt.subplots(figsize=(6, 4))
    wall.plot(power, thinnest, "o-", color="tab:blue")
    wall.set_xlabel("panel power [W]")
    wall.set_ylabel("thinnest wall [% of the sheet]", color="tab:blue")
    heat = wall.twinx()
    heat.plot(power, hottest, "s--", color="tab:red")
    heat.set_ylabel("hottest place at the end [C]", color="tab:red")
    wall.set_title("Drape forming %s: thinnest wall against heater power" % size)
    figure.tight_layout()
    plot = os.path.join(out, "thinnest-vs-power.png")
    figure.savefig(plot, dpi=100)

    print("%10s %12s %12s" % ("power W", "thinnest %", "hottest C"))
    for p, t, h in zip(power, thinnest, hottest):
        print("%10.0f %12.1f %12.1f" % (p, t, h))
    print("%d of %d case(s) done; plot: %s" % (len(done), len(results["cases"]), plot))
    return results


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else os.path.join("out", "heater-study"))
