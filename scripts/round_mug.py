#!/usr/bin/env python3
"""Writes scenes/meshes/round_mug.obj: a round mug with a handle, as one closed, outward-oriented
triangle mesh (the scenes' cube_in_mug.yaml drops a cube into it).

The body is a 32-gon revolved about z: outside radius 0.04 m, inside 0.034 m, 0.09 m high, its
floor 0.01 m thick. The handle is a C of 1 cm thick bars, 6 mm wide, on the facet facing +x:
two arms (z 0.02-0.03 and 0.06-0.07 m) reaching 3 cm out, joined by a grip. The facet the handle
meets is split into a grid around the two arms' ends, and its neighbours take the grid's points
on their shared edges, so that no vertex lies on another triangle's edge.

Usage: python3 scripts/round_mug.py [OUT]   (default: scenes/meshes/round_mug.obj)
"""

import math
import os
import sys

SEGMENTS = 32
OUTER, INNER, HEIGHT, FLOOR = 0.04, 0.034, 0.09, 0.01
HALF_WIDTH = 0.003  # m: the handle's half width along y, within the facet's (3.9 mm)
ARMS = ((0.02, 0.03), (0.06, 0.07))  # m: the arms' z ranges, lower then upper
REACH, GRIP = 0.03, 0.01  # m: how far the handle reaches out of the facet, the grip's thickness


class Mesh:
    def __init__(self):
        self.vertices = []
        self.index = {}
        self.triangles = []

    def vertex(self, p):
        key = tuple(round(c, 12) for c in p)
        if key not in self.index:
            self.index[key] = len(self.vertices)
            self.vertices.append(p)
        return self.index[key]

    def fan(self, polygon):
        """A convex planar polygon (outward counter-clockwise), fanned from its first corner."""
        ids = [self.vertex(p) for p in polygon]
        for k in range(1, len(ids) - 1):
            self.triangles.append((ids[0], ids[k], ids[k + 1]))


def ring(radius, z, k):
    angle = 2 * math.pi * (k - 0.5) / SEGMENTS  # facet 0 (corners 0 and 1) faces +x
    return (radius * math.cos(angle), radius * math.sin(angle), z)


def facet_points(k):
    """The points on corner k's vertical outer edge where the handle's facet grid meets it."""
    levels = [z for arm in ARMS for z in arm]
    x, y, _ = ring(OUTER, 0, k)
    return [(x, y, z) for z in levels]


def build():
    mesh = Mesh()
    n = SEGMENTS
    x0 = ring(OUTER, 0, 0)[0]  # the handle facet's plane, x = x0
    y0 = ring(OUTER, 0, 1)[1]  # its half width
    if not HALF_WIDTH < y0:
        raise SystemExit(f"round_mug: the handle ({2 * HALF_WIDTH} m) is wider than its facet")
    for k in range(n):
        j = (k + 1) % n
        bottom_k, bottom_j = ring(OUTER, 0, k), ring(OUTER, 0, j)
        top_k, top_j = ring(OUTER, HEIGHT, k), ring(OUTER, HEIGHT, j)
        inner_top_k, inner_top_j = ring(INNER, HEIGHT, k), ring(INNER, HEIGHT, j)
        floor_k, floor_j = ring(INNER, FLOOR, k), ring(INNER, FLOOR, j)
        # inside: the wall (facing the axis) and the floor's top
        mesh.fan([floor_k, inner_top_k, inner_top_j, floor_j])
        mesh.fan([(0, 0, FLOOR), floor_k, floor_j])
        if k == 0:
            # the bottom and the rim take the grid's points on their edges along the facet
            mesh.fan([(0, 0, 0), bottom_j, (x0, HALF_WIDTH, 0), (x0, -HALF_WIDTH, 0), bottom_k])
            mesh.fan([inner_top_k, top_k, (x0, -HALF_WIDTH, HEIGHT), (x0, HALF_WIDTH, HEIGHT),
                      top_j, inner_top_j])
            continue
        mesh.fan([(0, 0, 0), bottom_j, bottom_k])
        mesh.fan([inner_top_k, top_k, top_j, inner_top_j])
        # the outside; the facets beside the handle's take the grid's points on their shared edge
        if k == 1:
            mesh.fan([bottom_j, top_j, top_k] + facet_points(k)[::-1] + [bottom_k])
        elif k == n - 1:
            mesh.fan([top_k, bottom_k, bottom_j] + facet_points(j) + [top_j])
        else:
            mesh.fan([bottom_k, bottom_j, top_j, top_k])
    # the handle's facet: a grid around the arms' ends, which are open into the handle
    ys = [-y0, -HALF_WIDTH, HALF_WIDTH, y0]
    zs = [0.0] + [z for arm in ARMS for z in arm] + [HEIGHT]
    for a in range(3):
        for b in range(5):
            if a == 1 and b in (1, 3):
                continue
            y_0, y_1, z_0, z_1 = ys[a], ys[a + 1], zs[b], zs[b + 1]
            mesh.fan([(x0, y_0, z_0), (x0, y_1, z_0), (x0, y_1, z_1), (x0, y_0, z_1)])
    # the handle: a C in x-z (counter-clockwise), extruded over y; its two ends on the facet
    (low_0, low_1), (high_0, high_1) = ARMS
    c = [(x0, low_0), (x0 + REACH, low_0), (x0 + REACH, high_1), (x0, high_1),
         (x0, high_0), (x0 + REACH - GRIP, high_0), (x0 + REACH - GRIP, low_1), (x0, low_1)]
    sides = [(0, 1, 6), (0, 6, 7), (1, 2, 5), (1, 5, 6), (2, 3, 4), (2, 4, 5)]
    def at(i, y):
        return (c[i][0], y, c[i][1])

    for a, b, d in sides:
        mesh.fan([at(a, -HALF_WIDTH), at(b, -HALF_WIDTH), at(d, -HALF_WIDTH)])
        mesh.fan([at(a, HALF_WIDTH), at(d, HALF_WIDTH), at(b, HALF_WIDTH)])
    for i in range(8):
        j = (i + 1) % 8
        if (i, j) in ((3, 4), (7, 0)):
            continue  # the ends, open into the facet's grid
        mesh.fan([at(i, -HALF_WIDTH), at(i, HALF_WIDTH), at(j, HALF_WIDTH), at(j, -HALF_WIDTH)])
    return mesh


def check(mesh):
    """Closed and consistently oriented (each edge once each way), outward (positive volume)."""
    edges = {}
    for t in mesh.triangles:
        for k in range(3):
            edge = (t[k], t[(k + 1) % 3])
            edges[edge] = edges.get(edge, 0) + 1
    for (a, b), count in edges.items():
        if count != 1 or edges.get((b, a)) != 1:
            raise SystemExit(f"round_mug: edge {a}-{b} is not shared by exactly two triangles")
    volume = 0.0
    for a, b, d in mesh.triangles:
        p, q, r = mesh.vertices[a], mesh.vertices[b], mesh.vertices[d]
        volume += (p[0] * (q[1] * r[2] - q[2] * r[1]) - p[1] * (q[0] * r[2] - q[2] * r[0]) +
                   p[2] * (q[0] * r[1] - q[1] * r[0])) / 6
    if volume <= 0:
        raise SystemExit(f"round_mug: volume {volume} m³; expected the mesh oriented outward")
    return volume


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.normpath(os.path.join(
        os.path.dirname(os.path.abspath(__file__)), "..", "scenes", "meshes", "round_mug.obj"))
    mesh = build()
    volume = check(mesh)
    lines = [
        "# A round mug with a handle, written by scripts/round_mug.py: a 32-gon about z, outside",
        "# radius 0.04 m, inside 0.034 m, 0.09 m high, its floor 0.01 m thick; on its +x facet a C",
        "# handle of 1 cm thick bars, 6 mm wide, its arms at z 0.02-0.03 and 0.06-0.07 m reaching",
        "# 3 cm out. Mesh frame: the bottom's centre at the origin, z up. Closed and outward-oriented",
        f"# ({len(mesh.triangles)} triangles, {volume:.6e} m³).",
    ]
    lines += [f"v {x:.17g} {y:.17g} {z:.17g}" for x, y, z in mesh.vertices]
    lines += [f"f {a + 1} {b + 1} {d + 1}" for a, b, d in mesh.triangles]
    tmp = out + ".tmp"
    with open(tmp, "w") as f:
        f.write("\n".join(lines) + "\n")
    os.replace(tmp, out)
    print(f"wrote {out}: {len(mesh.vertices)} vertices, {len(mesh.triangles)} triangles")


if __name__ == "__main__":
    main()
