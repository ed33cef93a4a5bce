#!/usr/bin/env python3
"""Writes the exact rational models in scenes/models/ (.rbpt, see src/scene/bpt.rs).

Both are surfaces of revolution about z built from quarter circles. A quarter
circle is the rational quadratic with weights 1, sqrt(2)/2, 1; degree-raised
to a cubic in homogeneous coordinates it has weights 1, (1 + 2s)/3,
(1 + 2s)/3, 1 (s = sqrt(2)/2). The patch control point (i along the sweep, j
along the profile) is the profile point rotated by the sweep's circle point,
with weight w_i * w_j (the tensor product of two rational curves).

  rational_torus.rbpt   16 patches, major radius 1, minor radius 0.35
  rational_sphere.rbpt   8 patches, radius 1 (poles are collapsed edges)

Points on patch boundaries are computed by one formula from exact corner
values, so patches that share a boundary share its points and weights
bitwise, which crack-free drawing needs. Usage: make.py OUT_DIR
"""
import math
import sys

S = math.sqrt(0.5)
W_MID = (1.0 + 2.0 * S) / 3.0

# The corners of the unit circle at 0, 90, 180, 270 degrees and the
# quadratic middle points of the quarters between them.
CORNERS = [(1.0, 0.0), (0.0, 1.0), (-1.0, 0.0), (0.0, -1.0)]
MIDDLES = [(1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0), (1.0, -1.0)]


def quarter(k):
    """Cubic control points (x, y) and weights of quarter k (counter-clockwise)."""
    a, m, b = CORNERS[k % 4], MIDDLES[k % 4], CORNERS[(k + 1) % 4]
    q1 = tuple((p + 2.0 * S * c) / (1.0 + 2.0 * S) for p, c in zip(a, m))
    q2 = tuple((2.0 * S * c + p) / (1.0 + 2.0 * S) for c, p in zip(m, b))
    return [a, q1, q2, b], [1.0, W_MID, W_MID, 1.0]


def revolve(profile_quarters, radius, centre):
    """Patches of the profile circle (radius, centre distance from the axis)
    swept once around z: u along the sweep, v along the profile, so that
    d/du x d/dv points out of the surface."""
    patches = []
    for k in range(4):
        sweep, sw = quarter(k)
        for q in profile_quarters:
            prof, pw = quarter(q)
            pts = []
            for j in range(4):
                rho = centre + radius * prof[j][0]
                z = radius * prof[j][1]
                for i in range(4):
                    c, s = sweep[i]
                    pts.append(((rho * c, rho * s, z), sw[i] * pw[j]))
            patches.append(pts)
    return patches


def fmt(x):
    # Shortest text that reads back as the same f32-rounded double; -0 as 0.
    x = 0.0 if x == 0.0 else x
    return repr(x)


def write(path, patches):
    index = {}
    points = []
    lines = []
    for p in patches:
        ids = []
        for (xyz, w) in p:
            key = tuple(fmt(v) for v in xyz) + (fmt(w),)
            if key not in index:
                points.append(key)
                index[key] = len(points)
            ids.append(str(index[key]))
        lines.append(",".join(ids))
    with open(path, "w") as f:
        f.write(f"{len(patches)}\n")
        f.write("\n".join(lines) + "\n")
        f.write(f"{len(points)}\n")
        for key in points:
            f.write(",".join(key) + "\n")


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "scenes/models"
    # Torus: the whole minor circle, 4 profile quarters.
    write(f"{out}/rational_torus.rbpt", revolve([0, 1, 2, 3], 0.35, 1.0))
    # Sphere: the profile from the south pole (270 degrees) up to the north
    # pole (90 degrees): quarters 3 and 0.
    write(f"{out}/rational_sphere.rbpt", revolve([3, 0], 1.0, 0.0))


main()
