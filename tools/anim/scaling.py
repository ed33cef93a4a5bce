#!/usr/bin/env python3
"""The update pass's cost against the number of animated cage vertices
(docs/BENCHMARKS.md, "Animation"): scenes of 1, 4 and 16 car cages, each its
own scene model with its own twist (so each is converted on its own), drawn
tiny (64x36: the update pass is what is measured), `render --repeat`.

    python3 tools/anim/scaling.py [REPEAT] [SIZES...]

Prints one line per scene: cars, cage vertices, model patches, point and
shading rows' terms, and the update pass's median, minimum and maximum ms.
"""

import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
BIN = os.path.join(ROOT, "target", "release", "bezier-subdiv")
CAR = os.path.join(ROOT, "scenes", "models", "catmark_car.obj")


def scene(n):
    s = ["[animation]", "duration = 4.0",
         "[camera]", "position = [0.0, -30.0, 20.0]", "target = [0.0, 0.0, 0.0]"]
    for k in range(n):
        s += ["[[model]]", f'name = "car {k}"', f'file = "{CAR}"',
              "[[model.deform]]", 'kind = "twist"', 'axis = "z"',
              "center = [0.6, -1.2, 0.0]", "angle_deg = [[0.0, 0.0], [4.0, 90.0]]",
              "[[model.instance]]", f"translate = [{2.0 * (k % 4)}, {4.0 * (k // 4)}, 0.0]"]
    return "\n".join(s) + "\n"


def main():
    repeat = sys.argv[1] if len(sys.argv) > 1 else "21"
    sizes = [int(x) for x in sys.argv[2:]] or [1, 4, 16]
    with tempfile.TemporaryDirectory() as d:
        for n in sizes:
            path = os.path.join(d, f"cars{n}.toml")
            with open(path, "w") as f:
                f.write(scene(n))
            png = os.path.join(d, f"cars{n}.png")
            subprocess.run([BIN, "render", "--scene", path, "--time", "1", "--size", "64x36",
                            "--repeat", repeat, "--out", png], check=True,
                           stdout=subprocess.DEVNULL)
            r = json.load(open(png[:-4] + ".json"))
            a = r["animation"]
            print(f"cars {n:2}: {a['vertices']:6} cage vertices, {a['patches']:6} model patches: "
                  f"update {r['gpu_ms']['update']:.3f} ms median of {r['repeat']} "
                  f"(min {r['gpu_ms_min']['update']:.3f}, max {r['gpu_ms_max']['update']:.3f}); "
                  f"{1e6 * r['gpu_ms']['update'] / a['vertices']:.0f} ns per vertex; "
                  f"animation buffers {r['memory_bytes']['animation']} bytes")


if __name__ == "__main__":
    main()
