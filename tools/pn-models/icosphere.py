#!/usr/bin/env python3
"""Writes scenes/models/pn_icosphere.obj: a unit icosphere (an icosahedron
with every triangle split into four, once: 80 triangles, 42 vertices) as a
closed triangle mesh for PN triangles (src/scene/pn.rs). No `vn` lines: the
reader averages the face normals around each vertex. Deliberately coarse,
so the PN surface visibly rounds the flat facets. Usage: icosphere.py OUT
"""
import math
import sys


def icosahedron():
    t = (1.0 + math.sqrt(5.0)) / 2.0
    v = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0),
         (0, -1, t), (0, 1, t), (0, -1, -t), (0, 1, -t),
         (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11),
         (1, 5, 9), (5, 11, 4), (11, 10, 2), (10, 7, 6), (7, 1, 8),
         (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9),
         (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    return [unit(p) for p in v], f


def unit(p):
    n = math.sqrt(sum(c * c for c in p))
    return tuple(c / n for c in p)


def split(v, f):
    mid = {}

    def middle(a, b):
        key = (min(a, b), max(a, b))
        if key not in mid:
            v.append(unit(tuple((x + y) / 2 for x, y in zip(v[a], v[b]))))
            mid[key] = len(v) - 1
        return mid[key]

    out = []
    for a, b, c in f:
        ab, bc, ca = middle(a, b), middle(b, c), middle(c, a)
        out += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
    return v, out


def main():
    v, f = split(*icosahedron())
    with open(sys.argv[1], "w") as out:
        out.write("# Unit icosphere, 80 triangles (tools/pn-models/icosphere.py)\n")
        for p in v:
            out.write("v %.9f %.9f %.9f\n" % p)
        for a, b, c in f:
            out.write("f %d %d %d\n" % (a + 1, b + 1, c + 1))


main()
