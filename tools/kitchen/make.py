#!/usr/bin/env python3
"""Writes the evaluation kitchen: its furniture cages and scenes/kitchen.toml.

The paper evaluates on "a Utah teapot as a native Bezier model together with
typical converted CCS assets" in a kitchen of 35,940 base patches (its §4,
Fig. 7). This builds one the way an artist would: a room whose floor, walls,
counter, cabinets, table and chairs are Catmull-Clark cages, exactly planar
where they are flat and rounded where a modeller rounds them, with the
teapot and the OpenSubdiv models (toy cars, pawns, tori, cube blobs) on and
around them.

Two kinds of furniture cage:

- creased boxes (chess squares, handle bars, books): a box of 8 vertices
  with its 12 edges tagged `t crease ... 10` (infinitely sharp). Every face
  converts to an exactly planar patch with evenly spaced control points.
- rounded boxes (table, legs, counter, cabinets, doors, chairs): a box cage
  with a support loop at distance r inside every edge (3 x 3 faces a side,
  54 in all), the usual way to round an edge in a subdivision modeller. The
  middle face of each side converts to an exactly planar patch whose
  control points are unevenly spaced (the loops are r from the edge, the
  middle span is long): flat geometry with uneven parameterisation, the
  case the paper's Fig. 3 separates by lambda. The edge and corner faces
  are curved; the corners are valence-3 extraordinary vertices.

Floor and walls are open planar sheets of quads (every patch planar with
evenly spaced control points). Everything is written in world units (z up; the
teapot is 6.4 wide; the table top is at z = 8) so no instance scales a
rounded box (which would stretch its rounding).

Usage: tools/kitchen/make.py [SCENES_DIR]   (default: scenes/ beside tools/)
Writes SCENES_DIR/models/kitchen_*.obj and SCENES_DIR/kitchen.toml, and
prints the patch table (which must come to 35,940).
"""
import os
import sys

TARGET_PATCHES = 35_940

# Patches per instance of the shipped models (what `import` reports).
SHIPPED = {
    "teapot.bpt": 32,
    "catmark_pawn.obj": 588,
    "catmark_torus.obj": 32,
    "catmark_cube.obj": 6,
    "catmark_car.obj": 1575,
}


# ---------------------------------------------------------------- cages


class Cage:
    """A quad cage being assembled: vertices, faces (counter-clockwise seen
    from outside, 0-based) and crease tags."""

    def __init__(self):
        self.v = []
        self.f = []
        self.creases = []
        self.comments = []
        self.boundary = False
        # Optional: a texture coordinate per vertex (written as one `vt`
        # per vertex, faces as v/vt) and a material (library, name).
        self.vt = None
        self.material = None

    def vertex(self, p):
        self.v.append(tuple(float(c) for c in p))
        return len(self.v) - 1

    def write(self, path, header):
        lines = ["# " + h for h in header]
        lines += ["# " + c for c in self.comments]
        if self.material:
            lines.append(f"mtllib {self.material[0]}")
        for x, y, z in self.v:
            lines.append(f"v {fmt(x)} {fmt(y)} {fmt(z)}")
        if self.vt:
            for s, t in self.vt:
                lines.append(f"vt {fmt(s)} {fmt(t)}")
        if self.material:
            lines.append(f"usemtl {self.material[1]}")
        for q in self.f:
            if self.vt:
                lines.append("f " + " ".join(f"{i + 1}/{i + 1}" for i in q))
            else:
                lines.append("f " + " ".join(str(i + 1) for i in q))
        for a, b in self.creases:
            lines.append(f"t crease 2/1/0 {a} {b} 10")
        if self.boundary:
            lines.append("t interpolateboundary 1/0/0 1")
        tmp = path + ".tmp"
        with open(tmp, "w") as out:
            out.write("\n".join(lines) + "\n")
        os.replace(tmp, path)


MATERIAL_MAPS = {"stone_tiles": "../textures/kitchen_floor.png"}


def write_material(path, material, obj):
    """The material library of `obj`: `material` with its albedo map."""
    text = (f"# {os.path.basename(path)}: written by tools/kitchen/make.py for {obj}.\n"
            f"# The map is made by tools/textures/make.py.\n"
            f"newmtl {material}\nKd 1 1 1\nmap_Kd {MATERIAL_MAPS[material]}\n")
    tmp = path + ".tmp"
    with open(tmp, "w") as out:
        out.write(text)
    os.replace(tmp, path)


def fmt(x):
    s = f"{x:.6f}".rstrip("0").rstrip(".")
    return "0" if s in ("-0", "") else s


def lattice_box(cage, xs, ys, zs):
    """The surface of the lattice xs x ys x zs (coordinates per axis,
    increasing): (len-1) faces per span on every side, outward. Returns the
    vertex index of each surface lattice point (i, j, k)."""
    nx, ny, nz = len(xs), len(ys), len(zs)
    index = {}

    def vid(i, j, k):
        key = (i, j, k)
        if key not in index:
            index[key] = cage.vertex((xs[i], ys[j], zs[k]))
        return index[key]

    def quad(a, b, c, d):
        cage.f.append((a, b, c, d))

    # -z (bottom) and +z (top)
    for i in range(nx - 1):
        for j in range(ny - 1):
            quad(vid(i, j, 0), vid(i, j + 1, 0), vid(i + 1, j + 1, 0), vid(i + 1, j, 0))
            k = nz - 1
            quad(vid(i, j, k), vid(i + 1, j, k), vid(i + 1, j + 1, k), vid(i, j + 1, k))
    # -y and +y
    for i in range(nx - 1):
        for k in range(nz - 1):
            quad(vid(i, 0, k), vid(i + 1, 0, k), vid(i + 1, 0, k + 1), vid(i, 0, k + 1))
            j = ny - 1
            quad(vid(i, j, k), vid(i, j, k + 1), vid(i + 1, j, k + 1), vid(i + 1, j, k))
    # -x and +x
    for j in range(ny - 1):
        for k in range(nz - 1):
            quad(vid(0, j, k), vid(0, j, k + 1), vid(0, j + 1, k + 1), vid(0, j + 1, k))
            i = nx - 1
            quad(vid(i, j, k), vid(i, j + 1, k), vid(i, j + 1, k + 1), vid(i, j, k + 1))
    return index


def creased_box(cage, lo, hi):
    """A box whose 12 edges are infinitely sharp: 6 planar patches."""
    index = lattice_box(cage, [lo[0], hi[0]], [lo[1], hi[1]], [lo[2], hi[2]])
    corners = [(i, j, k) for i in (0, 1) for j in (0, 1) for k in (0, 1)]
    for a in corners:
        for b in corners:
            if a < b and sum(x != y for x, y in zip(a, b)) == 1:
                cage.creases.append((index[a], index[b]))


def rounded_box(cage, lo, hi, r):
    """A box rounded by a support loop r inside every edge: 54 patches."""
    axes = []
    for a, b in zip(lo, hi):
        rr = min(r, (b - a) / 3.0)
        axes.append([a, a + rr, b - rr, b])
    lattice_box(cage, *axes)


# ---------------------------------------------------------------- the room

# Floor: a planar sheet of 20 x 20 quads of 3 over [-30, 30]^2 at z = 0.
TILE_PITCH = 3.0
TILES = 20
# Walls: sheets of the same quads on the back (y = 30) and left (x = -30)
# walls, up to z = 24.
WALL_ROWS = 8
# The table: a 24 x 24 top 0.5 thick, top face at z = 8, rounded 0.2; four
# 0.8 x 0.8 legs rounded 0.12 under its corners.
TABLE_TOP = ((-12.0, -12.0, 7.5), (12.0, 12.0, 8.0))
LEG_XY = 10.6
LEG_HALF = 0.4
# The counter along the back wall: cabinets 5 wide, 4 deep, 8.4 tall, each
# with a door panel and a handle bar; one worktop over all of them.
CABINETS = 6
CAB_W = 5.0
CAB_X0 = -29.0
CAB_Y = (25.4, 29.4)
CAB_H = 8.4
# Chairs at both free sides of the table.
CHAIR_X = 15.0


def grid_sheet(cage, origin, du, dv, nu, nv):
    """An open planar sheet of nu x nv quads from `origin` along du, dv
    (faces counter-clockwise seen from du x dv): every patch planar with
    evenly spaced control points."""
    ids = [[cage.vertex(tuple(o + a * i + b * j for o, a, b in zip(origin, du, dv)))
            for i in range(nu + 1)] for j in range(nv + 1)]
    for j in range(nv):
        for i in range(nu):
            cage.f.append((ids[j][i], ids[j][i + 1], ids[j + 1][i + 1], ids[j + 1][i]))


def floor_cage():
    c = Cage()
    p = TILE_PITCH
    grid_sheet(c, (-30.0, -30.0, 0.0), (p, 0.0, 0.0), (0.0, p, 0.0), TILES, TILES)
    c.boundary = True
    c.comments.append(f"a planar sheet of {TILES} x {TILES} quads of {p} over [-30, 30]^2 at z = 0, facing +z")
    # Stone tiles: the map (tools/textures/make.py) holds 4 x 4 tiles, so
    # s, t = (x, y) / (4 p) puts one tile on each quad.
    c.vt = [((x + 30.0) / (4 * p), (y + 30.0) / (4 * p)) for x, y, _ in c.v]
    c.material = ("kitchen_floor.mtl", "stone_tiles")
    c.comments.append("texture coordinates: one stone tile of ../textures/kitchen_floor.png per quad (kitchen_floor.mtl)")
    return c


def wall_cage():
    c = Cage()
    p = TILE_PITCH
    # The back wall at y = 30 faces -y; the left wall at x = -30 faces +x.
    grid_sheet(c, (-30.0, 30.0, 0.0), (p, 0.0, 0.0), (0.0, 0.0, p), TILES, WALL_ROWS)
    grid_sheet(c, (-30.0, -30.0, 0.0), (0.0, p, 0.0), (0.0, 0.0, p), TILES, WALL_ROWS)
    c.boundary = True
    c.comments.append(f"back and left walls: planar sheets of {TILES} x {WALL_ROWS} quads of {p}")
    return c


def table_cage():
    c = Cage()
    lo, hi = TABLE_TOP
    rounded_box(c, lo, hi, 0.2)
    for sx in (-1, 1):
        for sy in (-1, 1):
            cx, cy = sx * LEG_XY, sy * LEG_XY
            # The legs' tops end inside the top (hidden), bottoms on the floor.
            rounded_box(c, (cx - LEG_HALF, cy - LEG_HALF, 0.0), (cx + LEG_HALF, cy + LEG_HALF, 7.7), 0.12)
    c.comments.append("table: a rounded 24 x 24 x 0.5 top (top face at z = 8) on four rounded legs")
    return c


def counter_cage():
    c = Cage()
    y0, y1 = CAB_Y
    for n in range(CABINETS):
        x0 = CAB_X0 + CAB_W * n
        rounded_box(c, (x0 + 0.05, y0, 0.0), (x0 + CAB_W - 0.05, y1, CAB_H), 0.1)
        # The door: a panel proud of the cabinet front (y = y0).
        rounded_box(c, (x0 + 0.35, y0 - 0.12, 0.6), (x0 + CAB_W - 0.35, y0 + 0.02, CAB_H - 0.5), 0.05)
        # The handle: a creased bar on the door.
        creased_box(c, (x0 + 1.0, y0 - 0.32, CAB_H - 1.3), (x0 + CAB_W - 1.0, y0 - 0.12, CAB_H - 1.1))
    x_end = CAB_X0 + CAB_W * CABINETS
    rounded_box(c, (CAB_X0 - 0.3, y0 - 0.5, CAB_H), (x_end + 0.3, 29.9, CAB_H + 0.6), 0.15)
    c.comments.append(f"counter: {CABINETS} rounded cabinets with doors and handle bars under one rounded worktop")
    return c


def chair_cage():
    """One chair facing +x, centred at the origin (instances rotate it)."""
    c = Cage()
    h = 4.6  # seat top
    rounded_box(c, (-2.0, -2.0, h - 0.4), (2.0, 2.0, h), 0.15)
    for sx in (-1, 1):
        for sy in (-1, 1):
            cx, cy = sx * 1.6, sy * 1.6
            rounded_box(c, (cx - 0.25, cy - 0.25, 0.0), (cx + 0.25, cy + 0.25, h - 0.3), 0.08)
    rounded_box(c, (-2.0, -2.0, h), (-1.6, 2.0, h + 4.5), 0.12)
    c.comments.append("chair: rounded seat, four legs and a back; faces +x")
    return c


def books_cage():
    """Books standing on the worktop: creased boxes of varied sizes."""
    c = Cage()
    x = -8.0
    z0 = CAB_H + 0.6
    sizes = [(0.35, 2.2, 3.0), (0.5, 2.4, 3.4), (0.3, 2.0, 2.6), (0.45, 2.3, 3.2), (0.4, 2.1, 2.9),
             (0.6, 2.5, 3.6), (0.3, 1.9, 2.5), (0.4, 2.2, 3.1), (0.5, 2.3, 3.3), (0.35, 2.0, 2.8)]
    for w, d, hgt in sizes:
        creased_box(c, (x, 29.6 - d, z0), (x + w, 29.6, z0 + hgt))
        x += w + 0.05
    c.comments.append(f"{len(sizes)} books standing on the worktop")
    return c


FURNITURE = {
    # file: (cage builder, patches per instance counted from the cage)
    "kitchen_floor.obj": floor_cage,
    "kitchen_walls.obj": wall_cage,
    "kitchen_table.obj": table_cage,
    "kitchen_counter.obj": counter_cage,
    "kitchen_chair.obj": chair_cage,
    "kitchen_books.obj": books_cage,
}


# ---------------------------------------------------------------- the scene

SCENE_HEAD = '''# The evaluation scene: a kitchen with the Utah teapot (a native Bezier
# model) among converted Catmull-Clark assets, like the paper's (§4: "a Utah
# teapot as a native Bezier model together with typical converted CCS
# assets", 35,940 base patches). Written by tools/kitchen/make.py, which also
# writes the furniture cages: edit the script, not this file.
#
#   model         file                     instances × patches = base patches
{table}
#                                                      ------
#                                                      {total:>6,}
#
# Units: the teapot is 6.4 wide and 3.15 tall; z is up. The floor is at
# z = 0, the table top at z = 8. Floor and walls are planar sheets of quads;
# chess squares, handle bars and books are creased boxes (both: exactly
# planar faces, evenly spaced control points); table, legs, cabinets, doors, worktop and
# chairs are rounded boxes (support loops: planar middles with unevenly
# spaced control points, curved edges, extraordinary corners).
#
# The previous kitchen of flattened cube blobs is scenes/blobs.toml.
#
# Models appear in this order on purpose: the preview palette tints by model
# index. `stats --preview` shows the scene.
name = "kitchen"

[view]
eps = 1.0
lambda = 0.5
'''

CAMERAS = '''
# Frame 0: over the cars in front, looking down at the table, with the floor
# and the counter behind it receding, so fine and coarse subdivision share
# the picture.
[camera]
position = [20.0, -38.0, 21.0]
target = [0.0, -2.0, 4.0]
up = [0.0, 0.0, 1.0]
fov_y_deg = 45.0
near = 0.05
far = 500.0

[camera_path]
frames = 240

# 1: close to the teapot's spout.
[[camera_path.key]]
position = [0.5, -4.7, 10.9]
target = [-0.9, -3.2, 10.3]
fov_y_deg = 45.0
near = 0.02
far = 500.0

# 2: low in the aisle between the two front rows of cars, looking along it.
[[camera_path.key]]
position = [-13.0, -21.0, 0.9]
target = [0.0, -21.0, 0.6]
fov_y_deg = 50.0
near = 0.02
far = 500.0

# 3: far away: the whole room small in the picture, seen from outside its
# open corner.
[[camera_path.key]]
position = [120.0, -140.0, 80.0]
target = [0.0, 0.0, 3.0]
fov_y_deg = 30.0
near = 0.5
far = 1000.0

# 4: over the chessboard, close to the black pawns.
[[camera_path.key]]
position = [6.5, -3.0, 11.0]
target = [3.6, 2.0, 8.2]
fov_y_deg = 45.0
near = 0.02
far = 500.0

# 5: grazing along the table top from its edge, past the donuts to the teapot.
[[camera_path.key]]
position = [-15.0, 8.0, 8.6]
target = [0.0, -1.0, 8.0]
fov_y_deg = 45.0
near = 0.02
far = 500.0

# 6: steeply down on the table top: teapot, ring stacks, donuts, chessboard.
[[camera_path.key]]
position = [-1.0, -11.0, 18.0]
target = [-0.5, 0.0, 8.0]
fov_y_deg = 50.0
near = 0.05
far = 500.0

# 7: from the table towards the counter: cabinets, doors, worktop, books and
# the tiled walls.
[[camera_path.key]]
position = [4.0, 6.0, 11.0]
target = [-10.0, 27.0, 6.0]
fov_y_deg = 50.0
near = 0.05
far = 500.0

# The path `bench` samples (like the paper's Fig. 7 animation): one turn
# around the table with three approaches, each from far over the floor and
# the cars down to just beside the table top, always inside the room (the
# walls are one-sided sheets: from outside, the ground truth, which culls
# nothing, would show their backs).
[camera_orbit]
center = [0.0, 0.0, 7.0]
distance = [13.0, 26.0]
height = [6.0, 11.0]
turns = 1.0
waves = 3.0
start_deg = 40.0
fov_y_deg = 45.0
near = 0.05
far = 500.0
frames = 240
'''

MODELS = '''
[[model]]
name = "floor"
file = "models/kitchen_floor.obj"

[[model]]
name = "walls"
file = "models/kitchen_walls.obj"

[[model]]
name = "counter"
file = "models/kitchen_counter.obj"

[[model]]
name = "books"
file = "models/kitchen_books.obj"

[[model]]
name = "table"
file = "models/kitchen_table.obj"

# Two chairs at the table's free sides, facing it.
[[model]]
name = "chairs"
file = "models/kitchen_chair.obj"
[[model.instance]]
translate = [-{chair_x}, 0.0, 0.0]
[[model.instance]]
translate = [{chair_x}, 0.0, 0.0]
rotate_deg = [0.0, 0.0, 180.0]

# Chessboard: 8 x 8 creased squares of pitch 0.85 (0.81 wide, 0.1 high, tops
# at z = 8.1) centred at (3.6, 1.2), a dark square at a1.
[[model]]
name = "chess light"
file = "models/kitchen_square.obj"
[[model.instance]]
translate = [1.475, -1.775, 8.0]
grid = {{ count = [4, 4, 1], step = [1.7, 1.7, 0.0] }}
[[model.instance]]
translate = [0.625, -0.925, 8.0]
grid = {{ count = [4, 4, 1], step = [1.7, 1.7, 0.0] }}

[[model]]
name = "chess dark"
file = "models/kitchen_square.obj"
[[model.instance]]
translate = [0.625, -1.775, 8.0]
grid = {{ count = [4, 4, 1], step = [1.7, 1.7, 0.0] }}
[[model.instance]]
translate = [1.475, -0.925, 8.0]
grid = {{ count = [4, 4, 1], step = [1.7, 1.7, 0.0] }}

# The teapot on the table, spout towards the chessboard. Its body, spout and
# handle are open surfaces that intersect: two-sided.
[[model]]
name = "teapot"
file = "models/teapot.bpt"
two_sided = true
[[model.instance]]
translate = [-4.0, -3.2, 8.0]

# Pawns (0.75 tall at scale 1.5) on the second and seventh ranks. The cage's
# centre axis is at (1.747, -1.275) with its base at z = 0.026, hence the
# offsets. The pawn's bottom is open, but it always stands on a square and
# the table is between it and any camera below, so it stays one-sided.
[[model]]
name = "white pawns"
file = "models/catmark_pawn.obj"
[[model.instance]]
translate = [-1.9955, 0.9875, 8.061]
scale = 1.5
grid = {{ count = [8, 1, 1], step = [0.85, 0.0, 0.0] }}

[[model]]
name = "black pawns"
file = "models/catmark_pawn.obj"
[[model.instance]]
translate = [-1.9955, 5.2375, 8.061]
scale = 1.5
grid = {{ count = [8, 1, 1], step = [0.85, 0.0, 0.0] }}

# Donuts: a 6 x 3 tray of tori lying flat (the torus cage's ring is in the
# x/z plane; 90 degrees about x lays it down). Closed surfaces: one-sided.
[[model]]
name = "donuts"
file = "models/catmark_torus.obj"
[[model.instance]]
translate = [-6.875, 3.45, 8.136]
rotate_deg = [90.0, 0.0, 0.0]
scale = 0.45
grid = {{ count = [6, 3, 1], step = [1.15, 1.15, 0.0] }}

# Toy cars (scale 1.5: 5.6 long, 2.4 wide, 1.1 tall) parked on the floor: two
# front rows facing each other across an aisle, and a back row. The car cage
# is open (wheel arches, underside): two-sided. Its centre is at
# (0.62, -1.86) with the wheels' bottom at z = -0.031, hence the offsets.
[[model]]
name = "toy cars"
file = "models/catmark_car.obj"
two_sided = true
[[model.instance]]
translate = [-7.729, -14.21, 0.0465]
scale = 1.5
grid = {{ count = [5, 1, 1], step = [3.4, 0.0, 0.0] }}
[[model.instance]]
translate = [-5.871, -27.79, 0.0465]
rotate_deg = [0.0, 0.0, 180.0]
scale = 1.5
grid = {{ count = [5, 1, 1], step = [3.4, 0.0, 0.0] }}
[[model.instance]]
translate = [-4.171, 14.21, 0.0465]
rotate_deg = [0.0, 0.0, 180.0]
scale = 1.5
grid = {{ count = [{back_cars}, 1, 1], step = [3.4, 0.0, 0.0] }}

# Tyres: four stacks of five tori beside the back row. Closed: one-sided.
[[model]]
name = "tyres"
file = "models/catmark_torus.obj"
[[model.instance]]
translate = [-13.5, 16.5, 0.1944]
rotate_deg = [90.0, 0.0, 0.0]
scale = 0.6
grid = {{ count = [2, 2, 5], step = [27.0, 3.0, 0.3888] }}

# Balls: the cube cage's limit surface is nearly round, so the blobs are
# toy balls (2.0 across), lying about on the floor.
[[model]]
name = "balls"
file = "models/catmark_cube.obj"
[[model.instance]]
translate = [-19.5, -7.5, 0.994]
rotate_deg = [0.0, 0.0, 45.0]
scale = 1.2
[[model.instance]]
translate = [-16.5, -4.5, 0.994]
rotate_deg = [0.0, 0.0, 45.0]
scale = 1.2
[[model.instance]]
translate = [19.5, -4.5, 0.994]
rotate_deg = [0.0, 0.0, 45.0]
scale = 1.2
[[model.instance]]
translate = [21.5, 4.5, 0.994]
rotate_deg = [0.0, 0.0, 45.0]
scale = 1.2
[[model.instance]]
translate = [-19.5, 7.5, 0.994]
rotate_deg = [0.0, 0.0, 45.0]
scale = 1.2

# Ring stacks: two stacks of six rings on the table, right of the teapot.
[[model]]
name = "ring stacks"
file = "models/catmark_torus.obj"
[[model.instance]]
translate = [2.5, -5.2, 8.166]
rotate_deg = [90.0, 0.0, 0.0]
scale = 0.55
grid = {{ count = [2, 1, 6], step = [2.5, 0.0, 0.3564] }}
'''


def square_cage():
    c = Cage()
    creased_box(c, (-0.405, -0.405, 0.0), (0.405, 0.405, 0.1))
    c.comments.append("a chess square: a creased box 0.81 x 0.81 x 0.1, its top at z = 0.1")
    return c


FURNITURE["kitchen_square.obj"] = square_cage


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    scenes = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "..", "scenes")
    models = os.path.join(scenes, "models")
    os.makedirs(models, exist_ok=True)
    patches = {}
    for name, build in FURNITURE.items():
        cage = build()
        cage.write(
            os.path.join(models, name),
            [f"{name}: written by tools/kitchen/make.py for scenes/kitchen.toml.",
             f"{len(cage.f)} quads, {len(cage.creases)} infinitely sharp edges."],
        )
        if cage.material:
            write_material(os.path.join(models, cage.material[0]), cage.material[1], name)
        patches[name] = len(cage.f)
    patches.update(SHIPPED)

    # Instances per model, in scene order; the back row of cars takes up
    # whatever the patch budget leaves (checked to come out exact).
    rows = [
        ("floor", "kitchen_floor.obj", 1),
        ("walls", "kitchen_walls.obj", 1),
        ("counter", "kitchen_counter.obj", 1),
        ("books", "kitchen_books.obj", 1),
        ("table", "kitchen_table.obj", 1),
        ("chairs", "kitchen_chair.obj", 2),
        ("chess light", "kitchen_square.obj", 32),
        ("chess dark", "kitchen_square.obj", 32),
        ("teapot", "teapot.bpt", 1),
        ("white pawns", "catmark_pawn.obj", 8),
        ("black pawns", "catmark_pawn.obj", 8),
        ("donuts", "catmark_torus.obj", 18),
        ("toy cars", "catmark_car.obj", None),
        ("tyres", "catmark_torus.obj", 20),
        ("balls", "catmark_cube.obj", 5),
        ("ring stacks", "catmark_torus.obj", 12),
    ]
    fixed = sum(patches[f] * n for _, f, n in rows if n is not None)
    cars, rest = divmod(TARGET_PATCHES - fixed, patches["catmark_car.obj"])
    if rest != 0 or cars < 10:
        sys.exit(f"make.py: the furniture leaves {TARGET_PATCHES - fixed} patches for the cars, "
                 f"not a multiple of {patches['catmark_car.obj']}: adjust the books or tiles")
    back_cars = cars - 10
    table = []
    total = 0
    for name, f, n in rows:
        n = cars if n is None else n
        total += patches[f] * n
        table.append(f"#   {name:<13} {f:<22} {n:>5} × {patches[f]:>5} = {patches[f] * n:>6,}")
    assert total == TARGET_PATCHES, total
    text = SCENE_HEAD.format(table="\n".join(table), total=total) + CAMERAS
    text += MODELS.format(chair_x=fmt(CHAIR_X), back_cars=back_cars)
    path = os.path.join(scenes, "kitchen.toml")
    with open(path + ".tmp", "w") as out:
        out.write(text)
    os.replace(path + ".tmp", path)
    print("\n".join(t[1:] for t in table))
    print(f"  total {total:,} base patches -> {path}")
    write_displaced(scenes, text)


# The displaced kitchen's last keyframe, after the kitchen's.
DISPLACED_KEY = '''# 8 (the displaced kitchen's own): low over the floor's left side, along
# the grout to the table and the balls.
[[camera_path.key]]
position = [-26.0, 4.0, 3.0]
target = [-14.0, -5.0, 0.0]
fov_y_deg = 45.0
near = 0.05
far = 500.0

'''


def write_displaced(scenes, text):
    """scenes/kitchen-displaced.toml: the kitchen with its floor's stone
    tiles displaced by their height map (grout 0.15 deep on 3-unit tiles;
    tools/textures/make.py writes the map) and one more keyframe, down on
    the floor; frames 0-7 are the kitchen's."""
    head = ("# The evaluation kitchen with a displaced floor (issue 40): written by\n"
            "# tools/kitchen/make.py from scenes/kitchen.toml; edit the script.\n"
            "# Frames 0-7 are the kitchen's; frame 8 looks along the floor's grout.\n#\n")
    text = head + text.replace('name = "kitchen"\n', 'name = "kitchen-displaced"\n', 1)
    orbit = "# The path `bench` samples"
    assert orbit in text
    text = text.replace(orbit, DISPLACED_KEY + orbit, 1)
    floor = 'file = "models/kitchen_floor.obj"\n'
    assert floor in text
    text = text.replace(floor, floor + 'displacement = { map = "textures/kitchen_floor_height.png", scale = 0.15 }\n', 1)
    path = os.path.join(scenes, "kitchen-displaced.toml")
    with open(path + ".tmp", "w") as out:
        out.write(text)
    os.replace(path + ".tmp", path)
    print(f"  the same with a displaced floor -> {path}")


if __name__ == "__main__":
    main()
