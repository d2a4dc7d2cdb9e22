#!/usr/bin/python3
"""ctest ParaView.*: runs a scene with `masse run` and opens everything it wrote for ParaView with VTK's own readers
(Debian's python3-vtk9, the library ParaView is built on), checking it against summary.json; then renders the final
frame offscreen and checks that the sheet and an obstacle are in the picture.

usage: check_paraview_output.py MASSE SCENE OUTDIR

VTK 9.1 has no .pvd reader class (vtkPVDReader is ParaView's own), so the collection is parsed with vtkXMLDataParser,
the XML parser under every VTK XML reader, and each dataset it lists is opened with vtkXMLPolyDataReader.
"""
import json
import math
import os
import shutil
import subprocess
import sys

import vtkmodules.vtkIOImage  # noqa: F401  (PNG reader and writer)
import vtkmodules.vtkIOXML  # noqa: F401
import vtkmodules.vtkRenderingOpenGL2  # noqa: F401  (the rendering back end)
from vtkmodules.vtkIOImage import vtkPNGReader, vtkPNGWriter
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader
from vtkmodules.vtkIOXMLParser import vtkXMLDataParser
from vtkmodules.vtkRenderingCore import (vtkActor, vtkPolyDataMapper, vtkRenderer, vtkRenderWindow,
                                         vtkWindowToImageFilter)

failures = []


def check(condition, message):
    if not condition:
        failures.append(message)
        print("FAIL: " + message)
    return condition


def close(a, b, tolerance):
    """Equal within a relative tolerance (or absolute near zero): the files keep 9 significant digits."""
    return abs(a - b) <= tolerance * max(1.0, abs(a), abs(b))


def read_collection(path):
    parser = vtkXMLDataParser()
    parser.SetFileName(path)
    if not parser.Parse():
        sys.exit(f"{path}: vtkXMLDataParser cannot parse it")
    root = parser.GetRootElement()
    check(root.GetName() == "VTKFile" and root.GetAttribute("type") == "Collection",
          f"{path}: root is not a VTKFile of type Collection")
    collection = root.FindNestedElementWithName("Collection")
    entries = []
    for i in range(collection.GetNumberOfNestedElements()):
        e = collection.GetNestedElement(i)
        entries.append({"time": float(e.GetAttribute("timestep")), "part": int(e.GetAttribute("part")),
                        "name": e.GetAttribute("name"), "file": e.GetAttribute("file")})
    return entries


def read_polydata(path):
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(path)
    reader.Update()
    check(reader.GetErrorCode() == 0, f"{path}: vtkXMLPolyDataReader reports error {reader.GetErrorCode()}")
    return reader.GetOutput()


def field_strings(data, name):
    array = data.GetFieldData().GetAbstractArray(name)
    if array is None:
        return None
    return [array.GetValue(i) for i in range(array.GetNumberOfValues())]


def field_number(data, name):
    array = data.GetFieldData().GetArray(name)
    return None if array is None else array.GetValue(0)


def point_range(data, name):
    array = data.GetPointData().GetArray(name)
    return None if array is None else array.GetRange(-1 if array.GetNumberOfComponents() > 1 else 0)


def render(datasets, png, width=800, height=600):
    """The sheet in orange and the obstacles in blue (the room's floor grey), unlit so the colours stay exact; returns
    the colour of each kind (sheet, obstacle, floor)."""
    renderer = vtkRenderer()
    renderer.SetBackground(1, 1, 1)
    colours = {}
    for name, data in datasets:
        mapper = vtkPolyDataMapper()
        mapper.SetInputData(data)
        mapper.ScalarVisibilityOff()
        actor = vtkActor()
        actor.SetMapper(mapper)
        kind = name if name in ("sheet", "floor") else "obstacle"
        colour = {"sheet": (1.0, 0.5, 0.0), "floor": (0.5, 0.5, 0.5), "obstacle": (0.0, 0.2, 1.0)}[kind]
        colours[kind] = colour
        actor.GetProperty().SetColor(*colour)
        actor.GetProperty().SetAmbient(1.0)
        actor.GetProperty().SetDiffuse(0.0)
        actor.GetProperty().SetSpecular(0.0)
        actor.GetProperty().LightingOff()
        renderer.AddActor(actor)
    sheet = dict(datasets)["sheet"]
    cx, cy, cz = sheet.GetCenter()
    camera = renderer.GetActiveCamera()
    camera.SetFocalPoint(cx, cy - 0.2, cz)
    camera.SetPosition(cx + 1.0, cy + 0.5, cz + 1.5)  # in front, to the right and a little above: the sheet's top
    camera.SetViewUp(0, 1, 0)                         # and, under it, the block and the plate's side
    renderer.ResetCameraClippingRange()
    window = vtkRenderWindow()
    window.SetOffScreenRendering(1)
    window.SetSize(width, height)
    window.AddRenderer(renderer)
    window.Render()
    grab = vtkWindowToImageFilter()
    grab.SetInput(window)
    grab.Update()
    writer = vtkPNGWriter()
    writer.SetFileName(png)
    writer.SetInputConnection(grab.GetOutputPort())
    writer.Write()
    return colours


def count_colours(png, colours):
    """Pixels of each colour (within 8 of 255 per channel) in the PNG as read back by vtkPNGReader."""
    reader = vtkPNGReader()
    reader.SetFileName(png)
    reader.Update()
    image = reader.GetOutput()
    scalars = image.GetPointData().GetScalars()
    components = scalars.GetNumberOfComponents()
    targets = {name: tuple(round(255 * c) for c in colour) for name, colour in colours.items()}
    counts = {name: 0 for name in colours}
    for i in range(scalars.GetNumberOfTuples()):
        pixel = [scalars.GetComponent(i, c) for c in range(min(3, components))]
        for name, target in targets.items():
            if all(abs(p - t) <= 8 for p, t in zip(pixel, target)):
                counts[name] += 1
    return counts, image.GetDimensions()


def main():
    masse, scene, out = sys.argv[1:4]
    shutil.rmtree(out, ignore_errors=True)
    run = subprocess.run([masse, "run", scene, "--out", out], capture_output=True, text=True)
    print(run.stdout[-2000:], run.stderr[-2000:])
    if run.returncode != 0:
        sys.exit(f"masse run failed with {run.returncode}")
    with open(os.path.join(out, "summary.json")) as f:
        summary = json.load(f)
    with open(scene) as f:
        spec = json.load(f)
    frames_every = spec["output"]["frames_every"]
    # Every polyhedron, and the room's floor when there is a room (its walls and ceiling are left out).
    expected_obstacles = {o["name"] for o in spec["obstacles"]}
    if spec.get("environment", {}).get("room", {}).get("enabled", True):
        expected_obstacles.add("floor")
    still_obstacles = {o["name"] for o in spec["obstacles"] if "path" not in o} | {"floor"}
    steps, dt, masses, springs = summary["steps"], summary["dt"], summary["masses"], summary["springs"]
    final = summary["final"]

    # The collection: one timestep per frame (every k steps and the final state), the simulated time of each.
    entries = read_collection(os.path.join(out, "frames.pvd"))
    expected_steps = list(range(0, steps + 1, frames_every))
    if expected_steps[-1] != steps:
        expected_steps.append(steps)
    check(steps % frames_every != 0, f"the scene should end between frames ({steps} steps, every {frames_every})")
    times = sorted({e["time"] for e in entries})
    check(len(times) == len(expected_steps), f"{len(times)} timesteps in frames.pvd, expected {len(expected_steps)}")
    for t, step in zip(times, expected_steps):
        check(close(t, step * dt, 1e-8), f"timestep {t} s, expected step {step} at {step * dt} s")
    check(close(times[-1], summary["sim_seconds"], 1e-8),
          f"last timestep {times[-1]} s, summary.json says {summary['sim_seconds']} s")

    parts = {}
    for e in entries:
        parts.setdefault(e["part"], set()).add(e["name"])
    check(all(len(names) == 1 for names in parts.values()), f"a part changes its name: {parts}")
    names = {part: next(iter(n)) for part, n in parts.items()}
    check(names.get(0) == "sheet", f"part 0 is {names.get(0)}, expected the sheet")
    obstacle_parts = {part: name for part, name in names.items() if part != 0}
    check(set(obstacle_parts.values()) == expected_obstacles,
          f"obstacles listed: {sorted(obstacle_parts.values())}, expected {sorted(expected_obstacles)}")
    for t in times:
        at = [e for e in entries if e["time"] == t]
        check(sorted(e["part"] for e in at) == sorted(names), f"at {t} s the collection lists parts {at}")

    # Every dataset: opens, its TimeValue is its timestep, the sheet's points and lines are the masses and springs.
    collection_dir = out
    frames = {}
    plate_heights = []
    block_files = set()
    for e in entries:
        path = os.path.join(collection_dir, e["file"])
        if not check(os.path.isfile(path), f"{e['file']} is listed but missing"):
            continue
        data = read_polydata(path)
        # A still obstacle's one file serves every timestep and has no time of its own.
        time_value = field_number(data, "TimeValue")
        if e["name"] not in still_obstacles:
            check(time_value is not None and close(time_value, e["time"], 1e-8),
                  f"{e['file']}: TimeValue {time_value} is not {e['time']}")
        if e["name"] == "sheet":
            frames[e["time"]] = data
            check(data.GetNumberOfPoints() == masses, f"{e['file']}: {data.GetNumberOfPoints()} points, {masses} masses")
            check(data.GetNumberOfLines() == springs, f"{e['file']}: {data.GetNumberOfLines()} lines, {springs} springs")
            check(data.GetNumberOfPolys() > 0, f"{e['file']}: no surface triangles")
            for array, components in (("velocity_m_s", 3), ("speed_m_s", 1), ("strain", 1), ("pinned", 1),
                                      ("contact_obstacle", 1), ("temperature_C", 1), ("thickness_m", 1)):
                a = data.GetPointData().GetArray(array)
                if check(a is not None, f"{e['file']}: no point array {array}"):
                    check(a.GetNumberOfTuples() == masses and a.GetNumberOfComponents() == components,
                          f"{e['file']}: {array} has {a.GetNumberOfTuples()}x{a.GetNumberOfComponents()} values")
        else:
            check(field_strings(data, "obstacle_name") == [e["name"]], f"{e['file']}: obstacle_name is not {e['name']}")
            check(data.GetNumberOfPolys() >= 6 and data.GetNumberOfPoints() >= 8, f"{e['file']}: not a box's faces")
            if e["name"] == "rising plate":
                plate_heights.append((e["time"], data.GetCenter()[1], e["file"]))
            if e["name"] == "block":
                block_files.add(e["file"])
    check(len(block_files) == 1, f"the still block should be one file, got {sorted(block_files)}")
    plate_heights.sort()
    check(len({f for _, _, f in plate_heights}) == len(times), "the moving plate needs a file per frame")
    check(all(b[1] > a[1] for a, b in zip(plate_heights, plate_heights[1:])),
          f"the plate's height should rise frame by frame: {[round(h, 4) for _, h, _ in plate_heights]}")
    for t, h, _ in plate_heights:  # the path: y from -0.2 at 0 s to 0.01 at 0.5 s, then still
        expected = -0.2 + 0.21 * min(t, 0.5) / 0.5
        check(abs(h - expected) < 1e-6, f"plate centre at {t} s is y = {h}, its path says {expected}")

    # The final frame against summary.json: bounding box, temperature and thickness ranges, contacts by name.
    last = frames[times[-1]]
    bounds = last.GetBounds()
    for axis in range(3):
        check(close(bounds[2 * axis], final["bbox_min"][axis], 1e-8) and
              close(bounds[2 * axis + 1], final["bbox_max"][axis], 1e-8),
              f"final frame bounds {bounds} against the summary's box {final['bbox_min']} {final['bbox_max']}")
    lo, hi = point_range(last, "temperature_C")
    check(close(lo, final["temperature_c"]["min"], 1e-8) and close(hi, final["temperature_c"]["max"], 1e-8),
          f"temperature_C {lo}..{hi} C, summary {final['temperature_c']}")
    check(hi > lo, "the panel should heat the sheet unevenly")
    lo, hi = point_range(last, "thickness_m")
    check(close(lo, final["thickness"]["min"], 1e-8), f"thickness_m minimum {lo} m, summary {final['thickness']}")
    check(0 < lo <= hi < 0.0021, f"thickness_m {lo}..{hi} m for a 2 mm sheet")
    speeds = last.GetPointData().GetArray("speed_m_s")
    velocities = last.GetPointData().GetArray("velocity_m_s")
    check(all(close(speeds.GetValue(i), math.sqrt(sum(c * c for c in velocities.GetTuple3(i))), 1e-7)
              for i in range(masses)), "speed_m_s is not the length of velocity_m_s")
    obstacle_names = field_strings(last, "obstacle_names")
    contact = last.GetPointData().GetArray("contact_obstacle")
    touched = {contact.GetValue(i) for i in range(masses)} - {-1}
    check(obstacle_names is not None and all(0 <= o < len(obstacle_names) for o in touched),
          f"contact_obstacle values {touched} outside the table obstacle_names {obstacle_names}")
    contact_events = {e["object"] for e in summary["events"] if e["name"] == "contact"}
    touched_names = {obstacle_names[o] for o in touched} if obstacle_names else set()
    check("rising plate" in contact_events, f"the plate should touch the sheet; contact events: {contact_events}")
    check(touched_names and touched_names <= contact_events,
          f"final frame touches {touched_names}, summary's contact events {contact_events}")
    pinned = last.GetPointData().GetArray("pinned")
    check(pinned.GetRange()[1] == 1, "the clamped edges should be pinned")

    # The OBJ of the final state, with the springs as lines (output.obj_springs).
    obj = os.path.join(out, "frames", f"frame_{steps:06d}.obj")
    if check(os.path.isfile(obj), f"{obj} missing: the final state must be a frame"):
        with open(obj) as f:
            kinds = [line.split(" ", 1)[0] for line in f]
        check(kinds.count("v") == masses and kinds.count("l") == springs,
              f"{obj}: {kinds.count('v')} vertices and {kinds.count('l')} lines, expected {masses} and {springs}")

    # Units in the CSV header.
    with open(os.path.join(out, "events.csv")) as f:
        header = f.readline().strip()
    check(header == "name,object,sim_time_s,wall_time_s", f"events.csv header: {header}")

    # The final frame rendered offscreen: the sheet and an obstacle (the block or the plate) are both in the picture.
    t = times[-1]
    datasets = [(e["name"], read_polydata(os.path.join(out, e["file"]))) for e in entries if e["time"] == t]
    png = os.path.join(out, "final-frame.png")
    colours = render(datasets, png)
    counts, size = count_colours(png, colours)
    pixels = size[0] * size[1]
    print(f"{png}: {size[0]}x{size[1]}, pixels by colour: {counts}")
    check(counts["sheet"] > 0.02 * pixels, f"the sheet covers {counts['sheet']} of {pixels} pixels")
    check(counts["obstacle"] > 0.01 * pixels, f"the block and the plate cover {counts['obstacle']} of {pixels} pixels")

    print(f"{len(entries)} datasets in {len(times)} timesteps checked; {len(failures)} failures")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
