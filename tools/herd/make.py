#!/usr/bin/env python3
"""Writes scenes/herd.toml: a million base patches, for issue 22.

A car park of 640 toy cars (OpenSubdiv's catmark_car, 1,575 patches each:
1,008,000 patches) in 20 rows of 32 on a floor, split in two halves by a
long wall, like CudaTess's "Killeroo herd" and nvpro's grid copies: many
instances of one model. Each model's patches are stored once on the GPU
and every car is a 96-byte instance record, so the scene's buffers stay
small; what a frame costs should follow what is seen. The camera path
comes down from far above the whole herd to among the cars, and its last
keys stand low behind the wall, where most of the herd is hidden.

The floor is the kitchen's planar sheet scaled up, the wall a creased box
(kitchen_square.obj) stretched: both exactly planar, so the cars are
almost all of the work.

Usage: tools/herd/make.py [SCENES_DIR]   (default: scenes/ beside tools/)
Prints the patch table, which must come to at least 1,000,000.
"""
import os
import sys

CAR_PATCHES = 1575
FLOOR_PATCHES = 400
WALL_PATCHES = 6

COLUMNS = 32
ROWS = 20
CAR_SCALE = 1.5
STEP_X = 3.6
STEP_Y = 7.2
# The car cage spans x 0..1.43 and y -3.76..0 before scaling: rows face +y.
CAR_WIDTH = 1.43 * CAR_SCALE
CAR_LENGTH = 3.76 * CAR_SCALE
Z_CAR = 0.0465 * CAR_SCALE


def f(x):
    """A number as the scene file writes it."""
    s = f"{x:.4f}".rstrip("0")
    return s + "0" if s.endswith(".") else s


def car_instances():
    """Two blocks of 10 rows, one on each side of the wall (y = 0)."""
    x0 = -(COLUMNS - 1) * STEP_X / 2 - CAR_WIDTH / 2
    out = []
    half = ROWS // 2
    for side, y_first in ((-1, -3.0), (1, 3.0 + CAR_LENGTH)):
        # The row nearest the wall first, then away from it.
        step = STEP_Y * side
        out.append(
            "[[model.instance]]\n"
            f"translate = [{f(x0)}, {f(y_first)}, {f(Z_CAR)}]\n"
            f"scale = {f(CAR_SCALE)}\n"
            f"grid = {{ count = [{COLUMNS}, {half}, 1], step = [{f(STEP_X)}, {f(step)}, 0.0] }}\n"
        )
    return out


CAMERA = """# The scene camera: far above the whole herd, looking down.
[camera]
position = [0.0, -150.0, 170.0]
target = [0.0, 0.0, 0.0]
up = [0.0, 0.0, 1.0]
fov_y_deg = 45.0
near = 0.5
far = 2000.0

[camera_path]
frames = 240

# 1: lower and oblique over one corner of the herd.
[[camera_path.key]]
position = [-90.0, -110.0, 45.0]
target = [-20.0, -30.0, 0.0]
fov_y_deg = 45.0
near = 0.2
far = 1000.0

# 2: just over the roofs in the front block, along a row.
[[camera_path.key]]
position = [-62.0, -26.0, 4.0]
target = [0.0, -24.0, 0.5]
fov_y_deg = 50.0
near = 0.05
far = 500.0

# 3: low among the cars, between two rows of the front block.
[[camera_path.key]]
position = [-30.0, -9.42, 1.2]
target = [10.0, -9.42, 0.7]
fov_y_deg = 50.0
near = 0.02
far = 500.0

# 4: low behind the wall, looking across it: the far block is hidden.
[[camera_path.key]]
position = [6.0, -45.0, 1.5]
target = [0.0, 40.0, 1.5]
fov_y_deg = 50.0
near = 0.05
far = 500.0

# 5: close to one car by the wall.
[[camera_path.key]]
position = [-4.5, -1.8, 1.8]
target = [-1.8, -5.8, 0.5]
fov_y_deg = 45.0
near = 0.01
far = 500.0

# The path `bench` samples: round the herd, coming down from high above to
# just over the roofs and back, twice.
[camera_orbit]
center = [0.0, 0.0, 0.0]
distance = [40.0, 160.0]
height = [6.0, 140.0]
turns = 1.0
waves = 2.0
start_deg = -90.0
fov_y_deg = 45.0
near = 0.05
far = 2000.0
frames = 240
"""


def scene_text():
    cars = car_instances()
    instances = COLUMNS * ROWS
    rows = [
        ("floor", "kitchen_floor.obj", 1, FLOOR_PATCHES),
        ("wall", "kitchen_square.obj", 1, WALL_PATCHES),
        ("cars", "catmark_car.obj", instances, CAR_PATCHES),
    ]
    total = sum(n * p for _, _, n, p in rows)
    table = "\n".join(
        f"#   {name:<8} {file:<20} {n:>4} × {p:>5} = {n * p:>9,}" for name, file, n, p in rows
    )
    head = f"""# A million base patches (issue 22): {instances} toy cars (catmark_car, {CAR_PATCHES:,}
# patches each) in {ROWS} rows of {COLUMNS} on a floor, in two blocks either side of a
# long wall. Each model's patches are stored once on the GPU; a car is one
# instance record. Written by tools/herd/make.py: edit the script, not this file.
#
#   model    file          instances × patches = base patches
{table}
#                                                   ---------
#                                                   {total:>9,}
#
# Units as in the kitchen (z up; a car is {f(CAR_LENGTH)} long).
name = "herd"

[view]
eps = 1.0
lambda = 0.5

"""
    models = f"""
[[model]]
name = "floor"
file = "models/kitchen_floor.obj"
[[model.instance]]
scale = [2.6, 2.6, 1.0]

# The wall across the middle (y = 0): a creased box 150 long, 6 high.
[[model]]
name = "wall"
file = "models/kitchen_square.obj"
[[model.instance]]
scale = [185.0, 1.0, 60.0]

[[model]]
name = "cars"
file = "models/catmark_car.obj"
two_sided = true
"""
    return head + CAMERA + models + "".join(cars), total


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    scenes = sys.argv[1] if len(sys.argv) > 1 else os.path.join(here, "..", "..", "scenes")
    text, total = scene_text()
    assert total >= 1_000_000, total
    with open(os.path.join(scenes, "herd.toml"), "w", encoding="utf-8") as out:
        out.write(text)
    print(f"herd.toml: {total:,} base patches")


if __name__ == "__main__":
    main()
