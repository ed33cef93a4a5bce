#!/usr/bin/env python3
"""Writes the animation demo: the creased flag's cage and scenes/anim.toml.

The scene shows every animation source the renderer has (docs/GUIDE.md,
"Animation"):

- a torus (catmark_torus) twisted about its vertical axis by a keyed angle,
  0 -> 180 degrees -> 0 over the cycle, and bent along its upper half;
- a flag (a creased grid cage written here) waving: a wave deformer whose
  amplitude grows from the hoist, travelling along the fly;
- four pawns (catmark_pawn) hopping across a chess board of creased
  squares (kitchen_square), keyed translations;
- the Utah teapot (a patch file) turning, a keyed rotation.

It also writes scenes/kitchen-anim.toml: the evaluation kitchen with every
base patch moving, for the update pass's cost (docs/BENCHMARKS.md,
"Animation"): each of its models gets a small travelling wave of its own
(so each moving model keeps its own copy of its patches on the GPU), and
each instance bobs up and down on keys (its own transform at 0 and 4 s,
lifted at 2 s).

Edit this script, not the files it writes:

    python3 tools/anim/make.py
"""

import os
import tomllib

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
MODELS = os.path.join(ROOT, "scenes", "models")

# --- the flag cage -----------------------------------------------------------
# A 3 x 2 sheet in the x-z plane (y = 0), 12 x 8 quads, hoist at x = 0. Two
# infinitely sharp creases: a vertical seam at x = 1 and a horizontal fold
# at z = 1 over the fly half (ending inside the sheet). Boundary: the
# default edge-and-corner rule.
NX, NZ, W, H = 12, 8, 3.0, 2.0


def flag():
    vid = lambda i, k: k * (NX + 1) + i
    lines = [
        "# flag.obj: a creased flag for the animation demo (scenes/anim.toml).",
        "# Written by tools/anim/make.py (project's own data). Vertices row by",
        "# row from the bottom, 0-based index = row * 13 + column.",
    ]
    for k in range(NZ + 1):
        for i in range(NX + 1):
            lines.append(f"v {W * i / NX:.6f} 0.000000 {H * k / NZ:.6f}")
    for k in range(NZ):
        for i in range(NX):
            # Counter-clockwise seen from -y: front faces -y.
            a, b, c, d = vid(i, k), vid(i + 1, k), vid(i + 1, k + 1), vid(i, k + 1)
            lines.append(f"f {a + 1} {b + 1} {c + 1} {d + 1}")
    seam = [(vid(4, k), vid(4, k + 1)) for k in range(NZ)]
    fold = [(vid(i, 4), vid(i + 1, 4)) for i in range(6, NX)]
    for a, b in seam + fold:
        lines.append(f"t crease 2/1/0 {a} {b} 10")
    return "\n".join(lines) + "\n"


# --- the scene ----------------------------------------------------------------
# Pawn cage: centre (1.7468, -1.2749), bottom 0.0259; at scale 1.5 a
# translation T puts its centre at T + (2.6202, -1.9124) and its bottom at
# T.z + 0.0389. Squares (kitchen_square): 0.81 wide, 0.1 tall, centred.
SQUARE = 0.85
X0, Y0 = -1.275, -2.775


def cell(i, j):
    return (X0 + SQUARE * i, Y0 + SQUARE * j)


def pawn_at(x, y, z):
    return [round(x - 2.6202, 4), round(y + 1.9124, 4), round(z + 0.061, 4)]


def pawn_keys(i, delay):
    """Hops from row 0 to row 3 from `delay` on, and back from 2 s + `delay`,
    one row per 0.5 s, apex 0.35 above the board; at rest at 0 and 4 s."""
    keys = [(0.0, 0, 0.0)]
    for start, rows in [(delay, [0, 1, 2, 3]), (2.0 + delay, [3, 2, 1, 0])]:
        if start > keys[-1][0]:
            keys.append((start, rows[0], 0.0))
        for k in range(3):
            t = start + 0.5 * k
            keys.append((t + 0.25, (rows[k] + rows[k + 1]) / 2, 0.35))
            keys.append((t + 0.5, rows[k + 1], 0.0))
    keys.append((4.0, 0, 0.0))
    out = []
    for time, row, lift in keys:
        x, _ = cell(i, 0)
        y = Y0 + SQUARE * row
        out.append((round(time, 4), pawn_at(x, y, lift)))
    return out


def scene():
    s = []
    w = s.append
    w("# The animation demo: every source of motion the renderer has (deformers,")
    w("# keyed instances; docs/GUIDE.md, \"Animation\"). Written by")
    w("# tools/anim/make.py, which also writes models/flag.obj: edit the script,")
    w("# not this file.")
    w('name = "anim"')
    w("")
    w("[view]\neps = 1.0\nlambda = 0.5\n")
    w("[animation]\nduration = 4.0\nfps = 24.0\n")
    w("[camera]\nposition = [0.4, -8.2, 4.0]\ntarget = [0.3, 0.2, 0.9]\nup = [0.0, 0.0, 1.0]")
    w("fov_y_deg = 45.0\nnear = 0.05\nfar = 200.0\n")
    w("[camera_orbit]\ncenter = [0.3, 0.0, 1.0]\ndistance = [7.0, 12.0]\nheight = [2.0, 5.0]")
    w("turns = 1.0\nwaves = 1.0\nframes = 96\n")
    # Torus: twisted about z by up to 180 degrees, bent along its upper half.
    w("# A torus standing in the x-z plane, twisted about its vertical axis")
    w("# (180 degrees over its height at t = 2 s) and bent at the top.")
    w('[[model]]\nname = "torus"\nfile = "models/catmark_torus.obj"')
    w("[[model.deform]]\nkind = \"twist\"\naxis = \"z\"\ncenter = [0.0, 0.0, 0.0]")
    w("angle_deg = [[0.0, 0.0], [2.0, 180.0], [4.0, 0.0]]\nlength = 2.5")
    w("[[model.deform]]\nkind = \"bend\"\naxis = \"z\"\ntoward = \"x\"\ncenter = [0.0, 0.0, 0.0]")
    w("angle_deg = [[0.0, 0.0], [1.0, 45.0], [3.0, -45.0], [4.0, 0.0]]\nlength = 1.3")
    w("[[model.instance]]\ntranslate = [-3.6, 0.5, 1.65]\n")
    # Flag.
    w("# A creased flag waving: the wave grows from the hoist over 1.5 units.")
    w('[[model]]\nname = "flag"\nfile = "models/flag.obj"\ntwo_sided = true')
    w("[[model.deform]]\nkind = \"wave\"\naxis = \"y\"\nalong = \"x\"\ncenter = [0.0, 0.0, 0.0]")
    w("amplitude = 0.3\nwavelength = 1.6\nspeed = 1.0\ngrow = 1.5")
    w("[[model.instance]]\ntranslate = [2.0, 1.0, 0.6]\n")
    # Board.
    for name, (dx, dy) in [("light squares", (0, 0)), ("dark squares", (1, 0))]:
        w(f'[[model]]\nname = "{name}"\nfile = "models/kitchen_square.obj"')
        for ox, oy in [(dx, dy), (1 - dx, 1 - dy)]:
            x, y = cell(ox, oy)
            w(f"[[model.instance]]\ntranslate = [{x:.3f}, {y:.3f}, 0.0]")
            w("grid = { count = [2, 2, 1], step = [1.7, 1.7, 0.0] }")
        w("")
    # Pawns.
    w("# Four pawns hopping up the board and back, one after the other.")
    w('[[model]]\nname = "pawns"\nfile = "models/catmark_pawn.obj"')
    for i in range(4):
        w("[[model.instance]]")
        for time, t in pawn_keys(i, 0.125 * i):
            w("[[model.instance.key]]")
            w(f"time = {time}\ntranslate = {t}\nscale = 1.5")
    w("")
    # Teapot.
    w("# The teapot (a patch file) turning once per cycle.")
    w('[[model]]\nname = "teapot"\nfile = "models/teapot.bpt"\ntwo_sided = true')
    w("[[model.instance]]")
    for time, deg in [(0.0, 0.0), (4.0, 360.0)]:
        w("[[model.instance.key]]")
        w(f"time = {time}\ntranslate = [0.2, 3.2, 0.0]\nrotate_deg = [0.0, 0.0, {deg}]\nscale = 0.45")
    return "\n".join(s) + "\n"


def value(v):
    """A TOML value."""
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(float(v)) if isinstance(v, float) else str(v)
    if isinstance(v, str):
        return '"' + v + '"'
    if isinstance(v, list):
        return "[" + ", ".join(value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{k} = {value(x)}" for k, x in v.items()) + " }"
    raise TypeError(v)


def table(name, d, out, array=False):
    out.append(f"[[{name}]]" if array else f"[{name}]")
    for k, v in d.items():
        if not isinstance(v, (dict, list)) or (isinstance(v, list) and not (v and isinstance(v[0], dict))):
            out.append(f"{k} = {value(v)}")
        elif isinstance(v, dict) and k == "grid":
            out.append(f"{k} = {value(v)}")


def kitchen_anim():
    with open(os.path.join(ROOT, "scenes", "kitchen.toml"), "rb") as f:
        k = tomllib.load(f)
    out = [
        "# The evaluation kitchen with every base patch moving: each model waves,",
        "# each instance bobs (tools/anim/make.py writes this from kitchen.toml;",
        "# edit the script, not this file). For the animation update pass's cost.",
        f'name = "kitchen-anim"',
        "",
    ]
    table("view", k["view"], out)
    out.append("[animation]\nduration = 4.0\nfps = 24.0")
    table("camera", k["camera"], out)
    if "camera_path" in k:
        table("camera_path", k["camera_path"], out)
        for key in k["camera_path"].get("key", []):
            table("camera_path.key", key, out, array=True)
    if "camera_orbit" in k:
        table("camera_orbit", k["camera_orbit"], out)
    for m in k["model"]:
        out.append("")
        table("model", m, out, array=True)
        if not m["file"].endswith(".rbpt"):
            out.append("[[model.deform]]")
            out.append('kind = "wave"\naxis = "z"\nalong = "x"\namplitude = 0.02')
            out.append("wavelength = 2.0\nspeed = 0.5")
        for inst in m.get("instance", [{}]):
            out.append("[[model.instance]]")
            if "grid" in inst:
                out.append(f"grid = {value(inst['grid'])}")
            t = inst.get("translate", [0.0, 0.0, 0.0])
            for time, lift in [(0.0, 0.0), (2.0, 0.05), (4.0, 0.0)]:
                out.append("[[model.instance.key]]")
                out.append(f"time = {time}")
                out.append(f"translate = {value([t[0], t[1], t[2] + lift])}")
                if "rotate_deg" in inst:
                    out.append(f"rotate_deg = {value(inst['rotate_deg'])}")
                if "scale" in inst:
                    out.append(f"scale = {value(inst['scale'])}")
    return "\n".join(out) + "\n"


def main():
    with open(os.path.join(MODELS, "flag.obj"), "w") as f:
        f.write(flag())
    with open(os.path.join(ROOT, "scenes", "anim.toml"), "w") as f:
        f.write(scene())
    with open(os.path.join(ROOT, "scenes", "kitchen-anim.toml"), "w") as f:
        f.write(kitchen_anim())


if __name__ == "__main__":
    main()
