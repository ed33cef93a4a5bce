#!/usr/bin/env python3
"""Tables of the subdivision kernels' figures from a run of tools/gpu/kernel.txt.

    tools/gpu/kernel_table.py RESULTS.jsonl > table.md

RESULTS.jsonl is what ../shared/gpu/run.sh writes (one render stats object
per line, with the command that made it). Prints Markdown: the device and
commit; kitchen keyframes (persistent against per-depth subdivide time with
occlusion culling off, their ratio, and the target subdiv <= 0.9x
subdiv-indirect); the teapot, eps 0.25, aniso and the queue kernel with
rounds, dispatches, atomics and polls per node and memory; occlusion culling
on against off (kitchen, herd); the workgroup sweep against its best; the
node-memory sweep; and any frame that fell back to the per-depth rounds.
Times are the medians `render --repeat` wrote.
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
        arg(c, "kernel", "levels"),
        arg(c, "node-memory"),
        arg(c, "occlusion", "on"),
        arg(c, "split", "iso"),
    )


def per_node(s, k):
    n = max(s.get("nodes_processed", 0), 1)
    return "%.4f" % (s[k] / n) if k in s else "–"


def mib(r, purpose):
    b = r.get("memory_bytes", {}).get(purpose)
    return "%.2f" % (b / 2**20) if b is not None else "–"


def figures_row(label, r):
    s = r["method_stats"]
    rounds = s.get("rounds", s.get("iterations_max", "–"))
    polls = "barrier_polls" if "barrier_polls" in s else "idle_polls"
    memory = mib(r, "node_memory") if "node_memory" in r.get("memory_bytes", {}) else mib(r, "queue")
    return "| %s | %s | %.3f | %.3f | %.3f | %d | %s | %s | %s | %s | %s | %s |" % (
        label, s.get("kernel", "per-depth"), ms(r), ms(r, "sort") if "sort" in r["gpu_ms"] else 0.0,
        ms(r, "draw"), s["nodes_processed"], rounds, s.get("dispatches", "–"),
        per_node(s, "global_atomics"), per_node(s, polls), memory, s.get("fallback", "–"))


def main():
    rows = [r for r in load(sys.argv[1]) if r.get("rc", 0) == 0 and "gpu_ms" in r]
    if not rows:
        sys.exit("no render results")
    first = rows[0]
    print("Device: %s, driver %s, commit %s, %dx%d.\n"
          % (first["device"], first["driver"], first["commit"], first["width"], first["height"]))
    by = {key(r): r for r in rows}

    def base(scene, f, eps, m, occlusion="off", split="iso"):
        return by.get((scene, f, eps, m, None, "levels", None, occlusion, split))

    print("| kitchen frame | subdiv ms (min–max) | subdiv-indirect ms (min–max) | ratio (target ≤ 0.9) | draw ms |")
    print("|---|---|---|---|---|")
    for f in range(8):
        a = base("scenes/kitchen.toml", f, 1.0, "subdiv")
        b = base("scenes/kitchen.toml", f, 1.0, "subdiv-indirect")
        if not (a and b):
            continue
        print("| %d | %.3f (%s) | %.3f (%s) | %.2f | %.3f |"
              % (f, ms(a), rng(a), ms(b), rng(b), ms(a) / ms(b), ms(a, "draw")))

    print("\n| case | kernel | subdivide ms | sort ms | draw ms | nodes | rounds / iterations | "
          "dispatches | atomics/node | polls/node | node memory or queue MiB | fallback |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for scene, f, eps in [("scenes/kitchen.toml", 0, 1.0), ("scenes/teapot.toml", 0, 1.0),
                          ("scenes/kitchen.toml", 0, 0.25), ("scenes/kitchen.toml", 2, 1.0)]:
        label = "%s %d eps %g" % (scene.split("/")[-1], f, eps)
        for m in ["subdiv", "subdiv-indirect"]:
            for split in ["iso", "aniso"]:
                r = base(scene, f, eps, m, split=split)
                if r:
                    print(figures_row("%s %s %s" % (label, m, split), r))
        q = by.get((scene, f, eps, "subdiv", None, "queue", None, "off", "iso"))
        if q:
            print(figures_row("%s subdiv --kernel queue" % label, q))

    print("\n| occlusion culling | method | subdivide ms off | on | frame ms off | on | nodes off | on "
          "| rounds off | on | triangles off | on |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for scene, f in [("scenes/kitchen.toml", 0), ("scenes/herd.toml", 0), ("scenes/herd.toml", 4)]:
        for m in ["subdiv", "subdiv-indirect"]:
            off, on = base(scene, f, 1.0, m, "off"), base(scene, f, 1.0, m, "on")
            if not (off and on):
                continue
            so, sn = off["method_stats"], on["method_stats"]
            print("| %s %d | %s | %.3f | %.3f | %.3f | %.3f | %d | %d | %s | %s | %d | %d |"
                  % (scene.split("/")[-1], f, m, ms(off), ms(on), ms(off, "frame"), ms(on, "frame"),
                     so["nodes_processed"], sn["nodes_processed"], so.get("rounds"), sn.get("rounds"),
                     off["triangles"], on["triangles"]))

    for scene in ["scenes/kitchen.toml", "scenes/teapot.toml"]:
        sweep = sorted((int(k[4]), r) for k, r in by.items()
                       if k[4] and k[0] == scene and k[5] == "levels" and k[6] is None
                       and k[7] == "off")
        if not sweep:
            continue
        best = min(ms(r) for _, r in sweep)
        default = base(scene, 0, 1.0, "subdiv")
        print("\n| %s workgroups launched | joined | subdivide ms | vs best |" % scene.split("/")[-1])
        print("|---|---|---|---|")
        for g, r in sweep:
            print("| %d | %s | %.3f | %.2f |"
                  % (g, r["method_stats"].get("workgroups_joined", "–"), ms(r), ms(r) / best))
        if default:
            s = default["method_stats"]
            print("| default (%s) | %s | %.3f | %.2f (target ≤ 1.10) |"
                  % (s.get("workgroups"), s.get("workgroups_joined"), ms(default), ms(default) / best))

    mem = sorted((float(k[6]), k[3], r) for k, r in by.items() if k[6])
    if mem:
        print("\n| kitchen eps 0.25, node memory MiB | method | subdivide ms | rounds | rounds in parts | dispatches |")
        print("|---|---|---|---|---|---|")
        for m, method, r in mem:
            s = r["method_stats"]
            print("| %g | %s | %.3f | %s | %s | %s |" % (m, method, ms(r), s.get("rounds"),
                                                       s.get("rounds_split"), s.get("dispatches")))

    fell = [r for r in rows if r.get("method_stats", {}).get("fallback")]
    print("\nFrames that fell back to the per-depth rounds: %d%s"
          % (len(fell), "".join("\n- %s: %s" % (r["command"], r["method_stats"]["fallback"])
                                for r in fell)))


if __name__ == "__main__":
    main()
