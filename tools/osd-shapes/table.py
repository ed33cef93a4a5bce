#!/usr/bin/env python3
"""The per-shape table of docs/OPENSUBDIV.md, from two outputs:

    cargo test --release --test osd_reference every_opensubdiv_shape_converts \
        -- --nocapture > deviations.txt
    tools/osd-shapes/validate.sh OUT_DIR > validate.txt
    tools/osd-shapes/table.py deviations.txt validate.txt

Per shape: patches at isolate 0, the largest deviation from OpenSubdiv's
limit surface over the classes that are exact by construction (regular,
crease, corner) and the largest over the approximated ones (naming the
worst class), both in units of the control box's diagonal; then
validate's verdict and the hole test's checked pixels. A shape missing
from validate.txt (not run) shows "-".
"""
import re
import sys

EXACT = {"regular", "crease", "corner"}


def deviations(path):
    shapes = {}
    for line in open(path, encoding="utf-8"):
        m = re.match(r"(?:test \S+ \.\.\. )?(catmark_\S+)\s+(\d+)\s+(\S+)\s+([0-9.e+-]+)\s*$", line)
        if not m:
            continue
        name, patches, cls, dev = m.group(1), int(m.group(2)), m.group(3), float(m.group(4))
        s = shapes.setdefault(name, {"patches": patches, "exact": None, "approx": None})
        if cls in EXACT:
            s["exact"] = max(s["exact"] or 0.0, dev)
        elif s["approx"] is None or dev > s["approx"][1]:
            s["approx"] = (cls, dev)
    return shapes


def validations(path):
    runs = {}
    for line in open(path, encoding="utf-8"):
        m = re.match(r"(catmark_\S+)\s+(\S+)\s+(ok|FAIL)\s+(.*)$", line)
        if not m:
            continue
        px = re.search(r"\(([\d,]+) px checked\)", m.group(4))
        if px:
            shown = px.group(1)
        elif m.group(4).startswith("nothing checked"):
            shown = "0 (nothing checked)"
        else:
            shown = m.group(4)[:40]
        runs[m.group(1)] = (m.group(3), shown)
    return runs


def main():
    dev = deviations(sys.argv[1])
    val = validations(sys.argv[2])
    print("| shape | patches | exact classes | worst approximated class | validate | hole test px |")
    print("|---|---:|---:|---|---|---:|")
    for name in sorted(dev):
        s = dev[name]
        approx = f"{s['approx'][0]} {s['approx'][1]:.1e}" if s["approx"] else "none"
        exact = f"{s['exact']:.1e}" if s["exact"] is not None else "none"
        verdict, px = val.get(name, ("-", "-"))
        print(f"| {name[len('catmark_'):]} | {s['patches']:,} | {exact} | {approx} | {verdict} | {px} |")


if __name__ == "__main__":
    main()
