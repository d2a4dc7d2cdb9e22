#!/usr/bin/env python3
"""Writes the forming moulds in this folder: closed surfaces (every edge shared by two faces), wound so that normals
point out of the solid (into the cavity for a cavity's wall). Run from this folder: python3 make_moulds.py

  cup-mould.stl   binary STL: a 0.30 m square block, 0.12 m deep, top at y = 0, with a round cup cavity (rim radius
                  0.07 m, floor radius 0.055 m, depth 0.07 m; the rim rounded to 0.01 m)
  tray-mould.obj  OBJ: a 0.40 x 0.30 m block with a tray cavity (0.28 x 0.18 m at the rim, 5 degree draft, 0.04 m deep;
                  rim and floor edges rounded to 0.01 m, the corners seen from above to 0.02 m at the rim)
  cone-45.stl, cone-60.stl, cone-70.stl   ASCII STL: a block with a conical cavity of half-angle 45, 60 and 70
                  degrees (rim radius 0.08 m, to the apex), for the cone-law test
  plug.obj        OBJ: a closed cylinder, radius 0.045 m, height 0.06 m, bottom edge rounded to a 0.01 m radius,
                  centred on its axis with its bottom at y = 0 (the plug of the plug-assist scene)
"""
import math
import struct


def ring_on_square(half, n, y):
    """n points on a square of half-width `half`, at the angles of a circle's n points (corners included when
    n is a multiple of 8)."""
    points = []
    for k in range(n):
        a = 2 * math.pi * k / n
        c, s = math.cos(a), math.sin(a)
        scale = half / max(abs(c), abs(s))
        points.append((c * scale, y, s * scale))
    return points


def rounded_rectangle(hx, hz, corner, n, y):
    """n points (n a multiple of 4) at equal steps along a rectangle of half extents hx, hz whose corners are rounded to
    the radius `corner`, from (hx, 0) in the sense of circle(). The second, third and fourth quarters are the first's
    mirror images across x = 0 and z = 0, so the ring is as mirror-symmetric as the rectangle."""
    corner = min(corner, hx, hz)
    m = n // 4
    side_z, arc, side_x = hz - corner, math.pi / 2 * corner, hx - corner
    quarter = side_z + arc + side_x
    first = []
    for k in range(m):
        s = quarter * k / m
        if s < side_z:
            first.append((hx, s))
        elif s < side_z + arc:
            a = (s - side_z) / corner
            first.append((hx - corner + corner * math.cos(a), hz - corner + corner * math.sin(a)))
        else:
            first.append((hx - corner - (s - side_z - arc), hz))
    second = [(0.0, hz)] + [(-first[m - k][0], first[m - k][1]) for k in range(1, m)]
    third = [(-hx, 0.0)] + [(-first[k][0], -first[k][1]) for k in range(1, m)]
    fourth = [(0.0, -hz)] + [(first[m - k][0], -first[m - k][1]) for k in range(1, m)]
    return [(x, y, z) for x, z in first + second + third + fourth]


def arc(centre, radius, start, end, segments):
    """segments + 1 points (u, y) of a circular arc in a wall's profile, from angle start to end (radians)."""
    return [(centre[0] + radius * math.cos(start + (end - start) * k / segments),
             centre[1] + radius * math.sin(start + (end - start) * k / segments)) for k in range(segments + 1)]


def over_rim(slope, radius, segments):
    """The profile (u, y) of a rim rounded to `radius` in `segments` facets: from the top face (y = 0, outside the rim's
    line) over the round to where it meets a wall that moves in by `slope` per metre down from the rim's line."""
    centre = (slope * radius - radius * math.sqrt(1 + slope * slope), -radius)
    return arc(centre, radius, math.pi / 2, math.atan(slope), segments)


def circle(radius, n, y):
    return [(radius * math.cos(2 * math.pi * k / n), y, radius * math.sin(2 * math.pi * k / n)) for k in range(n)]


class Mesh:
    def __init__(self):
        self.vertices = []
        self.faces = []

    def add(self, points):
        start = len(self.vertices)
        self.vertices.extend(points)
        return list(range(start, start + len(points)))

    def strip(self, lower, upper, outward_up):
        """Quads between two rings of equal size (as two triangles each). A ring's points are at the angles of a
        circle's n points (n a multiple of 4), so a quad's mirror images across x = 0 and z = 0 are quads of the same
        strip; a quad that is not flat (at a tray's cut corner) is split along the diagonal whose mirror images are the
        mirror quads' diagonals (lower[k]-upper[k+1] in the first and third quarters, lower[k+1]-upper[k] in the
        others), so the surface is as mirror-symmetric as the rings are."""
        n = len(lower)
        for k in range(n):
            a, b = lower[k], lower[(k + 1) % n]
            c, d = upper[(k + 1) % n], upper[k]
            if (4 * k // n) % 2 == 0:
                triangles = [(a, b, c), (a, c, d)]
            else:
                triangles = [(a, b, d), (b, c, d)]
            if not outward_up:
                triangles = [(x, z, y) for x, y, z in triangles]
            self.faces += triangles

    def fan(self, ring, centre, reverse):
        n = len(ring)
        for k in range(n):
            a, b = ring[k], ring[(k + 1) % n]
            self.faces.append((centre, b, a) if reverse else (centre, a, b))

    def orient_outward(self):
        """Flips every face so its normal points away from the solid: checked by the signed volume (positive when
        outward) and fixed per face by a consistent-winding walk."""
        # Make winding consistent across shared edges (breadth-first), then fix the sign by the volume.
        from collections import defaultdict, deque
        edge_faces = defaultdict(list)
        for f, face in enumerate(self.faces):
            for k in range(3):
                a, b = face[k], face[(k + 1) % 3]
                edge_faces[(min(a, b), max(a, b))].append(f)
        for edge, fs in edge_faces.items():
            assert len(fs) == 2, f"open edge {edge}"
        done = [False] * len(self.faces)
        for seed in range(len(self.faces)):
            if done[seed]:
                continue
            done[seed] = True
            queue = deque([seed])
            while queue:
                f = queue.popleft()
                face = self.faces[f]
                for k in range(3):
                    a, b = face[k], face[(k + 1) % 3]
                    for g in edge_faces[(min(a, b), max(a, b))]:
                        if g == f or done[g]:
                            continue
                        other = self.faces[g]
                        # consistent: the neighbour has the edge as b -> a
                        same = any(other[j] == a and other[(j + 1) % 3] == b for j in range(3))
                        if same:
                            self.faces[g] = (other[0], other[2], other[1])
                        done[g] = True
                        queue.append(g)
        volume = 0.0
        for a, b, c in self.faces:
            pa, pb, pc = self.vertices[a], self.vertices[b], self.vertices[c]
            volume += (pa[0] * (pb[1] * pc[2] - pb[2] * pc[1]) - pa[1] * (pb[0] * pc[2] - pb[2] * pc[0]) +
                       pa[2] * (pb[0] * pc[1] - pb[1] * pc[0])) / 6
        if volume < 0:
            self.faces = [(a, c, b) for a, b, c in self.faces]

    def normal(self, face):
        a, b, c = (self.vertices[i] for i in face)
        u = [b[i] - a[i] for i in range(3)]
        v = [c[i] - a[i] for i in range(3)]
        n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
        length = math.sqrt(sum(x * x for x in n)) or 1
        return [x / length for x in n]

    def write_obj(self, path, comment):
        with open(path, "w") as out:
            out.write(f"# {comment}\n# written by make_moulds.py\n")
            for v in self.vertices:
                out.write("v %.9g %.9g %.9g\n" % v)
            for f in self.faces:
                out.write("f %d %d %d\n" % tuple(i + 1 for i in f))

    def write_ascii_stl(self, path, name):
        with open(path, "w") as out:
            out.write(f"solid {name}\n")
            for f in self.faces:
                out.write("  facet normal %.6g %.6g %.6g\n    outer loop\n" % tuple(self.normal(f)))
                for i in f:
                    out.write("      vertex %.9g %.9g %.9g\n" % self.vertices[i])
                out.write("    endloop\n  endfacet\n")
            out.write(f"endsolid {name}\n")

    def write_binary_stl(self, path, header):
        with open(path, "wb") as out:
            out.write(header.encode()[:80].ljust(80, b" "))
            out.write(struct.pack("<I", len(self.faces)))
            for f in self.faces:
                out.write(struct.pack("<3f", *self.normal(f)))
                for i in f:
                    out.write(struct.pack("<3f", *self.vertices[i]))
                out.write(struct.pack("<H", 0))


def block_with_cavity(outer_top, outer_bottom, cavity_rings, floor_centre):
    """A block whose top is the annulus between outer_top and the first cavity ring; the cavity's wall runs through
    cavity_rings (top to bottom) and closes with a fan to floor_centre (or at an apex when floor_centre is None and
    the last ring is a single point)."""
    m = Mesh()
    top = m.add(outer_top)
    bottom = m.add(outer_bottom)
    rings = [m.add(r) for r in cavity_rings]
    m.strip(bottom, top, True)  # outer walls
    m.fan(bottom, m.add([(0.0, outer_bottom[0][1], 0.0)])[0], False)  # base
    m.strip(rings[0], top, True)  # top face: annulus
    for upper, lower in zip(rings, rings[1:]):
        m.strip(lower, upper, True)
    m.fan(rings[-1], m.add([floor_centre])[0], False)
    m.orient_outward()
    return m


def main():
    n = 64
    # Round cup: rim radius 0.07, floor radius 0.055, depth 0.07, a 0.3 m block 0.12 m deep, its rim rounded to 10 mm
    # in three facets as the tray's is (see below): a sharp rim lets the upper layer of a sheet drawn over it come down
    # on the block's top beside the edge. The wall's profile is (u, y), u how far the wall stands inside the rim's
    # circle; the floor's edge stays sharp.
    cup_profile = over_rim((0.07 - 0.055) / 0.07, 0.01, 3) + [(0.07 - 0.055, -0.07)]
    cup = block_with_cavity(ring_on_square(0.15, n, 0.0), ring_on_square(0.15, n, -0.12),
                            [circle(0.07 - u, n, y) for u, y in cup_profile], (0.0, -0.07, 0.0))
    cup.write_binary_stl("cup-mould.stl", "MaSSE round cup mould (make_moulds.py)")
    # Tray: 0.28 x 0.18 at the rim, 5 degree draft, 0.04 deep, in a 0.40 x 0.30 block, its edges radiused as a real
    # tray mould's are: the rim and the floor's edge in 10 mm arcs of three facets, the corners seen from above in
    # 20 mm at the rim. A sharp rim cuts a coarse sheet drawn over it between its masses: the bottom layer's springs
    # cut the edge's corner and upper-layer masses come down on the rim. Facets cost contact time (a mass pressed
    # towards the mould searches some 20 mm around it, and every facet in reach is tested), so the arcs have no more
    # than the layers need. The wall's profile is given as (u, y), u how far the wall stands inside the rim's line;
    # each ring is the rim's rounded rectangle moved in by u.
    depth, rim, floor, plan_corner, segments = 0.04, 0.01, 0.01, 0.02, 3
    slope = math.tan(math.radians(5))  # the draft: the wall moves in by slope per metre down
    root = math.sqrt(1 + slope * slope)
    draft_angle = math.atan(slope)
    profile = over_rim(slope, rim, segments)
    profile += arc((floor * root - slope * (floor - depth), floor - depth), floor, math.pi + draft_angle,
                   1.5 * math.pi, segments)  # into the floor
    rings = [rounded_rectangle(0.14 - u, 0.09 - u, plan_corner - u, n, y) for u, y in profile]
    tray = block_with_cavity(rounded_rectangle(0.2, 0.15, 0.03, n, 0.0),
                             rounded_rectangle(0.2, 0.15, 0.03, n, -0.1), rings, (0.0, -depth, 0.0))
    tray.write_obj("tray-mould.obj", "MaSSE tray mould: 0.28 x 0.18 m at the rim, 5 degree draft, 0.04 m deep, "
                   "rim and floor edges radiused 0.01 m, corners 0.02 m")
    # Cones: rim radius 0.08, to the apex.
    for half_angle in (45, 60, 70):
        r0 = 0.08
        depth = r0 / math.tan(math.radians(half_angle))
        rings = [circle(r0, n, 0.0)]
        cone = block_with_cavity(ring_on_square(0.12, n, 0.0), ring_on_square(0.12, n, -depth - 0.03), rings,
                                 (0.0, -depth, 0.0))
        cone.write_ascii_stl(f"cone-{half_angle}.stl", f"cone_{half_angle}")
    # Plug: a closed cylinder whose bottom edge is rounded to a quarter circle of 10 mm in six facets (15 degrees
    # between neighbours), bottom at y = 0. Plugs are radiused so as not to mark the sheet; a sharp or chamfered edge
    # (two 45-degree turns) made the sheet wrapped over it chatter against the layer floor at 64x2x64.
    plug = Mesh()
    fillet = 0.01
    rings = [plug.add(circle(0.045, 32, 0.06))]
    for k in range(7):
        angle = math.pi / 2 * k / 6  # 0 on the side, pi / 2 on the bottom
        rings.append(plug.add(circle(0.045 - fillet + fillet * math.cos(angle), 32, fillet - fillet * math.sin(angle))))
    for k in range(len(rings) - 1):
        plug.strip(rings[k + 1], rings[k], True)
    plug.fan(rings[0], plug.add([(0.0, 0.06, 0.0)])[0], True)
    plug.fan(rings[-1], plug.add([(0.0, 0.0, 0.0)])[0], False)
    plug.orient_outward()
    plug.write_obj("plug.obj", "MaSSE plug: cylinder r 0.045 m, 0.06 m tall, bottom edge rounded to r 0.01 m, bottom at y = 0")


if __name__ == "__main__":
    main()
