#!/usr/bin/env python3
"""Writes a scene with N extra copies of every instance of another scene,
each moved by OFFSET + k * STEP (k = 0 .. N-1): the scenes issue 22's
"cost follows what is seen" is measured on (copies outside the frustum,
copies behind an occluder), with `render --repeat` beside the original.

Everything but the models is copied verbatim from SCENE; the model files
become absolute paths, so OUT.toml can live anywhere (e.g. under out/).

Usage:
  tools/bench/extra_instances.py SCENE OUT.toml --copies N \\
      --offset DX DY DZ [--step DX DY DZ]

For the kitchen (docs/BENCHMARKS.md, issue 22):
  outside the frustum of every keyframe (2 km below the floor):
    --copies 10 --offset 0 0 -2000
  behind the far wall of keyframe 7 (the wall is 24 high, the camera at 11):
    --copies 10 --offset 0 65 0 --step 0 40 0
"""
import argparse
import os
import tomllib


def value(v):
    if isinstance(v, list):
        return "[" + ", ".join(value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{ " + ", ".join(f"{k} = {value(x)}" for k, x in v.items()) + " }"
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return repr(v)
    return '"' + str(v).replace("\\", "\\\\").replace('"', '\\"') + '"'


def moved(instance, by):
    out = dict(instance)
    t = out.get("translate", [0.0, 0.0, 0.0])
    out["translate"] = [t[i] + by[i] for i in range(3)]
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene")
    ap.add_argument("out")
    ap.add_argument("--copies", type=int, required=True)
    ap.add_argument("--offset", type=float, nargs=3, required=True)
    ap.add_argument("--step", type=float, nargs=3, default=[0.0, 0.0, 0.0])
    ap.add_argument(
        "--models", help="comma-separated model names to copy (default: every model)"
    )
    a = ap.parse_args()
    text = open(a.scene, encoding="utf-8").read()
    scene = tomllib.loads(text)
    here = os.path.dirname(os.path.abspath(a.scene))
    # The part before the first model, verbatim (name, view, cameras, paths).
    head = text[: text.index("[[model]]")]
    out = [head.rstrip() + "\n"]
    for m in scene["model"]:
        out.append("\n[[model]]")
        for k, v in m.items():
            if k == "instance":
                continue
            if k == "file":
                v = os.path.join(here, v)
            out.append(f"{k} = {value(v)}")
        instances = m.get("instance", [{}])
        chosen = a.models is None or m.get("name") in a.models.split(",")
        copies = [] if not chosen else [
            moved(i, [a.offset[d] + k * a.step[d] for d in range(3)])
            for k in range(a.copies)
            for i in instances
        ]
        for i in instances + copies:
            out.append("[[model.instance]]")
            for k, v in i.items():
                out.append(f"{k} = {value(v)}")
    with open(a.out, "w", encoding="utf-8") as f:
        f.write("\n".join(out) + "\n")


if __name__ == "__main__":
    main()
