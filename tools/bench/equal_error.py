#!/usr/bin/env python3
"""Triangles at equal FLIP from a bench directory's flip.csv, any version.

`bench` computes this itself (report.md, "At equal image error"); this
script does the same from flip.csv alone, so runs of binaries older than
that section (for instance the commit before the inner tier changed) can be
put in one table with new ones. Per configuration (method, eps, lambda) it
takes the medians over the perspectives of FLIP and of the triangles of the
FLIP images; the reference method's curve over eps is interpolated log-log
at each configuration's FLIP, as eval::pareto does.

  tools/bench/equal_error.py DIR [--reference tess] [--eps 1]

Prints one Markdown row per curve: triangles and FLIP at --eps, the ratio of
triangles to the reference's at that eps, and the median ratio at equal FLIP
over the eps values within the reference's range.
"""
import argparse
import csv
import math
import os
import statistics
from collections import defaultdict


def curves(path):
    rows = defaultdict(list)
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            key = (r["method"], r["lambda"], float(r["eps"]))
            rows[key].append((float(r["flip_mean"]), int(r["triangles"])))
    out = defaultdict(list)
    for (method, lam, eps), v in rows.items():
        flip = statistics.median(x[0] for x in v)
        tris = statistics.median(x[1] for x in v)
        out[(method, lam)].append((eps, flip, tris))
    for k in out:
        out[k].sort()
    return out


def at_flip(curve, flip):
    pts = sorted((f, t) for _, f, t in curve if f > 0)
    for f, t in pts:
        if f == flip:
            return t
    for (f1, t1), (f2, t2) in zip(pts, pts[1:]):
        if f1 < flip < f2:
            s = (math.log(flip) - math.log(f1)) / (math.log(f2) - math.log(f1))
            return math.exp(math.log(t1) + s * (math.log(t2) - math.log(t1)))
    return None


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dir")
    ap.add_argument("--reference", default="tess")
    ap.add_argument("--eps", type=float, default=1.0)
    a = ap.parse_args()
    cs = curves(os.path.join(a.dir, "flip.csv"))
    refs = [k for k in cs if k[0] == a.reference]
    if not refs:
        raise SystemExit(f"no {a.reference} in {a.dir}/flip.csv")
    ref = cs[refs[0]]
    ref_at_eps = {e: t for e, _, t in ref}
    print("| curve | triangles at ε | FLIP at ε | / reference at ε | / reference at equal FLIP (median, n) |")
    print("|---|---:|---:|---:|---:|")
    for (method, lam), c in cs.items():
        if method == a.reference:
            continue
        name = f"{method} λ={lam}" if lam else method
        at = [(e, f, t) for e, f, t in c if e == a.eps]
        ratios = [t / r for _, f, t in c if (r := at_flip(ref, f))]
        cell = f"{statistics.median(ratios):.3f}× ({len(ratios)})" if ratios else "–"
        if at:
            e, f, t = at[0]
            r = ref_at_eps.get(e)
            print(f"| {name} | {t:,.0f} | {f:.5f} | {t / r:.3f}× | {cell} |" if r else
                  f"| {name} | {t:,.0f} | {f:.5f} | – | {cell} |")
        else:
            print(f"| {name} | – | – | – | {cell} |")


if __name__ == "__main__":
    main()
