#!/usr/bin/env python3
"""Writes two four-patch test surfaces for the split direction (scenes/models/):

  cylinder.bpt  a tube of radius 2 and height 4 about z: cubic quarter
                circles around (u), straight rows evenly spaced along the
                axis (v). Curved one way, straight the other: what a 1:4
                split refines needlessly.
  pillow.bpt    a 2 x 2 patch sheet over [-2, 2]^2 bulging 1.5 high in the
                middle, curved alike in u and v: where 1:4 is right.

Both as one shared 4n x 7 (cylinder, around x along) or 7 x 7 (pillow) control
net, so neighbouring patches share their boundary points bit for bit.

And one test patch (tests/data/):

  aniso_deep.bpt  one 4 x 4 patch whose v boundaries (v = 0, 1) are
                  straight, curved a little along v at its sides and
                  bulging 8 high in u inside: under --split aniso at
                  eps 0.01, 3840 x 2160 its nodes split 1:2 along v, then
                  1:4, then 1:2 along u, twelve rounds in all, beyond the
                  l_max = 10 rounds an iso split can take
                  (tests/subdiv_gpu.rs).

Usage: tools/shapes/make.py [MODELS_DIR [TEST_DATA_DIR]]
"""
import math
import os
import sys

K = 4.0 / 3.0 * (math.sqrt(2.0) - 1.0)  # quarter-circle handle length


def fmt(x):
    s = f"{x:.9f}".rstrip("0").rstrip(".")
    return "0" if s in ("", "-0") else s


def write(path, points, patches):
    lines = [str(len(patches))]
    lines += [",".join(str(i + 1) for i in p) for p in patches]
    lines.append(str(len(points)))
    lines += [",".join(fmt(c) for c in p) for p in points]
    with open(path + ".tmp", "w") as f:
        f.write("\n".join(lines) + "\n")
    os.replace(path + ".tmp", path)


def cylinder(radius=2.0, height=4.0):
    # Around: 12 distinct points (4 quarters x 3, the 4th of each quarter
    # is the next one's first). Along: 4 evenly spaced rows.
    ring = []
    for q in range(4):
        a0 = q * math.pi / 2
        c0 = (math.cos(a0), math.sin(a0))
        c1 = (math.cos(a0 + math.pi / 2), math.sin(a0 + math.pi / 2))
        t0 = (-c0[1], c0[0])   # tangent at the start
        t1 = (c1[1], -c1[0])   # minus the tangent at the end
        ring += [c0, (c0[0] + K * t0[0], c0[1] + K * t0[1]), (c1[0] + K * t1[0], c1[1] + K * t1[1])]
    # Exact axis-aligned points (cos/sin of multiples of 90 degrees).
    ring = [tuple(round(c) if abs(c - round(c)) < 1e-12 else c for c in p) for p in ring]
    points = [(radius * x, radius * y, height * j / 3.0) for j in range(4) for (x, y) in ring]
    patches = []
    for q in range(4):
        idx = []
        for j in range(4):
            for i in range(4):
                idx.append(j * 12 + (3 * q + i) % 12)
        patches.append(idx)
    return points, patches


def pillow(half=2.0, bulge=1.5):
    n = 7
    points = []
    for j in range(n):
        for i in range(n):
            x = -half + 2 * half * i / (n - 1)
            y = -half + 2 * half * j / (n - 1)
            z = bulge * (1 - (x / half) ** 2) * (1 - (y / half) ** 2)
            points.append((x, y, z))
    patches = []
    for pj in range(2):
        for pi in range(2):
            patches.append([(3 * pj + j) * n + 3 * pi + i for j in range(4) for i in range(4)])
    return points, patches


def aniso_deep(side=0.2, bulge=8.0):
    # Rows j = 0, 3 flat (z = 0): straight v boundaries. Rows j = 1, 2 lift
    # the sides by `side` and the inner columns by `side + bulge`.
    points = []
    for j in range(4):
        for i in range(4):
            z = 0.0
            if j in (1, 2):
                z = side + (bulge if i in (1, 2) else 0.0)
            points.append((i / 3.0 * 4 - 2, j / 3.0 * 4 - 2, z))
    return points, [list(range(16))]


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.join(here, "..", "..")
    out = sys.argv[1] if len(sys.argv) > 1 else os.path.join(root, "scenes", "models")
    data = sys.argv[2] if len(sys.argv) > 2 else os.path.join(root, "tests", "data")
    os.makedirs(out, exist_ok=True)
    write(os.path.join(out, "cylinder.bpt"), *cylinder())
    write(os.path.join(out, "pillow.bpt"), *pillow())
    write(os.path.join(data, "aniso_deep.bpt"), *aniso_deep())


if __name__ == "__main__":
    main()
