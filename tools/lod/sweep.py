#!/usr/bin/env python3
"""Triangles against camera distance for a scene, levels of detail on and
off (issue 41): the scene's camera moved along its line of sight to each
distance, one `render` per distance and setting. Prints a Markdown table.

    python3 tools/lod/sweep.py [--scene scenes/herd.toml] [--size 960x540]
        [--factors 0.5,0.7,1,1.4,2,2.8,4] [--bin target/release/bezier-subdiv]
        [--lod-shading DEG]

Each distance is the scene camera's times a factor; the projected area of
the scene falls as 1/factor². With levels on the triangles should follow
that area; with them off they stay near two per visible patch.
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile


def camera_at(text, factor):
    """The scene text with [camera] position moved to `factor` times its
    distance from the target (scene files are relative to their folder)."""
    cam = re.search(r"\[camera\](.*?)(?=\n\[)", text, re.S).group(1)
    pos = [float(x) for x in re.search(r"position = \[([^\]]*)\]", cam).group(1).split(",")]
    tgt = [float(x) for x in re.search(r"target = \[([^\]]*)\]", cam).group(1).split(",")]
    new = [t + (p - t) * factor for p, t in zip(pos, tgt)]
    moved = re.sub(r"position = \[[^\]]*\]", "position = [%s]" % ", ".join("%.4f" % v for v in new), cam, count=1)
    return text.replace(cam, moved, 1)


def render(binary, scene, size, lod, shading):
    out = tempfile.mktemp(suffix=".png")
    cmd = [binary, "render", "--scene", scene, "--size", size, "--lod", lod, "--out", out]
    if shading is not None and lod == "on":
        cmd += ["--lod-shading", shading]
    subprocess.run(cmd, check=True, capture_output=True)
    stats = json.load(open(out[:-4] + ".json"))
    os.remove(out)
    os.remove(out[:-4] + ".json")
    return stats


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--scene", default="scenes/herd.toml")
    ap.add_argument("--size", default="960x540")
    ap.add_argument("--factors", default="0.5,0.7,1,1.4,2,2.8,4")
    ap.add_argument("--bin", default="target/release/bezier-subdiv")
    ap.add_argument("--lod-shading", default=None, help="the levels' shading bound (render's default if not given)")
    a = ap.parse_args()
    text = open(a.scene).read()
    folder = os.path.dirname(os.path.abspath(a.scene))
    print("| distance × | relative area | triangles, levels off | triangles, levels on | instances from levels | on/off |")
    print("|---:|---:|---:|---:|---:|---:|")
    for f in [float(x) for x in a.factors.split(",")]:
        path = os.path.join(folder, ".sweep-%s.toml" % f)
        with open(path, "w") as fh:
            fh.write(camera_at(text, f))
        try:
            off = render(a.bin, path, a.size, "off", a.lod_shading)
            on = render(a.bin, path, a.size, "on", a.lod_shading)
        finally:
            os.remove(path)
        lod = on.get("levels_of_detail") or {}
        print("| %g | %.3f | %s | %s | %s | %.3f |" % (
            f, 1 / (f * f), f"{off['triangles']:,}", f"{on['triangles']:,}",
            lod.get("instances", 0), on["triangles"] / max(off["triangles"], 1)))
        sys.stdout.flush()


if __name__ == "__main__":
    main()
