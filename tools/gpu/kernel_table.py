#!/usr/bin/env python3
"""Tables of the subdivision kernels' figures from a run of tools/gpu/kernel.txt.

    tools/gpu/kernel_table.py RESULTS.jsonl > table.md

RESULTS.jsonl is what ../shared/gpu/run.sh writes (one render stats object
per line, with the command that made it). Prints Markdown: the device and
commit, kitchen keyframes (persistent vs per-depth subdivide time and their
ratio), the teapot and eps 0.25, the workgroup sweep, and queue use against
the targets of issue 7. Times are the medians `render --repeat` wrote.
"""

import json
import re
import sys


def load(path):
    with open(path) as f:
        return [json.loads(line) for line in f if line.strip()]


def arg(cmd, name, default=None):
    m = re.search(r"--%s (\S+)" % name, cmd)
    return m.group(1) if m else default


def ms(r, scope="subdivide"):
    return r.get("gpu_ms", {}).get(scope, float("nan"))


def rng(r, scope="subdivide"):
    lo = r.get("gpu_ms_min", {}).get(scope, float("nan"))
    hi = r.get("gpu_ms_max", {}).get(scope, float("nan"))
    return "%.3f–%.3f" % (lo, hi)


def key(r):
    c = r["command"]
    return (
        arg(c, "scene", ""),
        int(arg(c, "frame", "0")),
        float(arg(c, "eps", "1")),
        arg(c, "method", "subdiv"),
        arg(c, "groups"),
    )


def main():
    rows = [r for r in load(sys.argv[1]) if r.get("rc", 0) == 0 and "gpu_ms" in r]
    if not rows:
        sys.exit("no render results")
    first = rows[0]
    print("Device: %s, driver %s, commit %s, %dx%d.\n"
          % (first["device"], first["driver"], first["commit"], first["width"], first["height"]))
    by = {key(r): r for r in rows}

    print("| kitchen frame | subdiv ms (min–max) | subdiv-indirect ms (min–max) | ratio | sort ms | draw ms |")
    print("|---|---|---|---|---|---|")
    for f in range(7):
        a = by.get(("scenes/kitchen.toml", f, 1.0, "subdiv", None))
        b = by.get(("scenes/kitchen.toml", f, 1.0, "subdiv-indirect", None))
        if not (a and b):
            continue
        print("| %d | %.3f (%s) | %.3f (%s) | %.2f | %.3f | %.3f |"
              % (f, ms(a), rng(a), ms(b), rng(b), ms(a) / ms(b), ms(a, "sort"), ms(a, "draw")))

    print("\n| case | method | subdivide ms | nodes | iterations_max | atomics/node | queue peak | spills |")
    print("|---|---|---|---|---|---|---|---|")
    for scene, eps in [("scenes/teapot.toml", 1.0), ("scenes/kitchen.toml", 0.25)]:
        for m in ["subdiv", "subdiv-indirect"]:
            r = by.get((scene, 0, eps, m, None))
            if not r:
                continue
            s = r["method_stats"]
            print("| %s eps %g | %s | %.3f | %d | %s | %s | %s | %s |"
                  % (scene.split("/")[-1], eps, m, ms(r), s["nodes_processed"],
                     s.get("iterations_max", "–"),
                     "%.3f" % s["global_atomics_per_node"] if "global_atomics_per_node" in s else "–",
                     s.get("queue_peak_items", "–"), s.get("queue_spills", "–")))

    sweep = sorted((int(k[4]), r) for k, r in by.items() if k[4] and k[0].endswith("kitchen.toml"))
    if sweep:
        best = min(ms(r) for _, r in sweep)
        default = by.get(("scenes/kitchen.toml", 0, 1.0, "subdiv", None))
        print("\n| workgroups | kitchen subdivide ms | vs best |")
        print("|---|---|---|")
        for g, r in sweep:
            print("| %d | %.3f | %.2f |" % (g, ms(r), ms(r) / best))
        if default:
            print("| default (%s) | %.3f | %.2f |"
                  % (default["method_stats"].get("workgroups"), ms(default), ms(default) / best))

    spills = [r for k, r in by.items()
              if k[0].endswith("kitchen.toml") and k[3] == "subdiv" and not k[4]]
    if spills:
        worst = max(spills, key=lambda r: r["method_stats"]["queue_peak_items"])
        total = sum(r["method_stats"]["queue_spills"] for r in spills)
        q = worst["memory_bytes"].get("queue", 0)
        print("\nQueue over %d kitchen views (keyframes x eps): %d spills, peak %d items in a "
              "%d-entry queue (%.1f MiB)."
              % (len(spills), total, worst["method_stats"]["queue_peak_items"],
                 worst["method_stats"]["queue_capacity_items"], q / 2**20))
        ind = [r for k, r in by.items() if k[3] == "subdiv-indirect" and k[0].endswith("kitchen.toml")]
        if ind:
            print("subdiv-indirect node buffers: %.1f MiB."
                  % (ind[0]["memory_bytes"].get("node_buffers", 0) / 2**20))


if __name__ == "__main__":
    main()
