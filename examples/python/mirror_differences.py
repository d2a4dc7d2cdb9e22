"""How far a formed part is from its own mirror image: runs a forming scene to its end and compares each mass's
thickness with the thickness at its mirror point across x = 0 and across z = 0, layer by layer, in h/h0. A part formed
on a mirror-symmetric mould from a mirror-symmetric set-up should be its own mirror image; what is left is the
lattice's own asymmetry (a TRiMM lattice's rows are shifted alternately) and anything in the step that depends on
the order of the masses.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/mirror_differences.py SCENE [KEY=VALUE ...]

KEY=VALUE pairs set scene keys as `masse run --set` does, e.g. sheet.structure=samm, sheet.size=33x2x25,
integrator.dt=0.005. Across z = 0 a mass is compared with the thickness of its layer's row at -z, read at the mass's
x (rows with no mirror row, as a TRiMM upper layer's, are left out); across x = 0 with its own row's thickness at -x.
A row's thickness between its masses is interpolated linearly. Prints the 99th percentile and the largest difference
of each, and the thinnest wall.
"""

import json
import sys

import numpy as np

import masse


def rows_of(coords, rest):
    """The masses of each (layer, row), in order of their rest x."""
    rows = {}
    for i, (layer, row, _) in enumerate(coords):
        rows.setdefault((int(layer), int(row)), []).append(i)
    return {key: sorted(masses, key=lambda i: rest[i, 0]) for key, masses in rows.items()}


def interpolated(masses, rest, h, x):
    """The thickness along one row at x (None outside the row), linear between its masses."""
    xs, hs = rest[masses, 0], h[masses]
    return np.interp(x, xs, hs) if xs[0] <= x <= xs[-1] else None


def across_z(rows, rest, h):
    """|h - h_mirror| for each mass whose layer has a row at its mirror z, h_mirror read along that row at its x."""
    row_z = {key: rest[masses[0], 2] for key, masses in rows.items()}
    out = []
    for (layer, row), masses in rows.items():
        mirror = [key for key, z in row_z.items() if key[0] == layer and abs(z + row_z[(layer, row)]) < 1e-9]
        if not mirror:
            continue
        for i in masses:
            other = interpolated(rows[mirror[0]], rest, h, rest[i, 0])
            if other is not None:
                out.append(abs(h[i] - other))
    return np.array(out)


def across_x(rows, rest, h):
    """|h(x) - h(-x)| along each row."""
    out = []
    for masses in rows.values():
        for i in masses:
            other = interpolated(masses, rest, h, -rest[i, 0])
            if other is not None:
                out.append(abs(h[i] - other))
    return np.array(out)


def value_of(text):
    """A --set value: JSON where it reads as JSON (numbers, true, false), else the text (samm, 33x2x25)."""
    try:
        return json.loads(text)
    except ValueError:
        return text


def main(scene_file, settings):
    overrides = {key: value_of(value) for key, value in (setting.split("=", 1) for setting in settings)}
    scene = masse.Scene.load(scene_file, overrides)
    scene.run()
    h0 = scene.summary()["final"]["thickness"]["initial"]
    h = np.array(scene.thickness) / h0
    rest = np.array(scene.rest_positions)
    rows = rows_of(np.array(scene.coords), rest)
    for name, differences in (("z", across_z(rows, rest, h)), ("x", across_x(rows, rest, h))):
        print("across %s = 0: %d masses, 99th percentile %.3f h0, largest %.3f h0"
              % (name, len(differences), np.percentile(differences, 99), differences.max()))
    print("thinnest wall %.3f h0" % h.min())


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit("usage: mirror_differences.py SCENE [KEY=VALUE ...]")
    main(sys.argv[1], sys.argv[2:])
