#!/usr/bin/env python3
"""Extracts OpenSubdiv's Catmull-Clark regression cages as OBJ files.

OpenSubdiv keeps its regression shapes as C++ headers, each one string
literal holding OBJ text (regression/shapes/catmark_*.h). This script reads
those headers from an OpenSubdiv checkout -- a work tree, or a bare git
directory such as the `fetch` tool's mirror, read with `git show` -- and
writes each cage's OBJ text unchanged but for two things: `vt`/`vn` lines
are dropped and face corners keep only their vertex index (the files
shrink by half). With `--keep-uv` the texture coordinates stay (`vt` lines,
`v/vt` corners; normals still go): the face-varying shapes
(`--only fvar`) are written so into tests/data/osd-fvar/. No
OpenSubdiv code is copied; the shapes are data under the Modified Apache
2.0 licence (scenes/models/LICENSE-OpenSubdiv.txt, NOTICE-OpenSubdiv.txt).

    tools/osd-shapes/extract.py OPENSUBDIV_DIR OUT_DIR [--rev REV]
        [--keep-uv] [--only SUBSTRING]

OPENSUBDIV_DIR is either a work tree (regression/shapes/ is read from disk)
or a git directory (the shapes are read at REV, default HEAD). Prints one
line per shape.
"""

import argparse
import pathlib
import re
import subprocess
import sys

# A C string literal: "..." with backslash escapes.
LITERAL = re.compile(r'"((?:[^"\\]|\\.)*)"')
ESCAPES = {"n": "\n", "t": "\t", '"': '"', "\\": "\\", "r": ""}


def unescape(body: str) -> str:
    out = []
    i = 0
    while i < len(body):
        c = body[i]
        if c == "\\" and i + 1 < len(body):
            nxt = body[i + 1]
            if nxt not in ESCAPES:
                raise ValueError(f"unknown escape \\{nxt}")
            out.append(ESCAPES[nxt])
            i += 2
        else:
            out.append(c)
            i += 1
    return "".join(out)


def obj_text(header: str, name: str) -> str:
    """The concatenated string literals after `NAME =`, unescaped."""
    start = header.find(f"{name} =")
    if start < 0:
        raise ValueError(f"no `{name} =` in the header")
    end = header.find(";", start)
    # `;` cannot occur inside the OBJ text of these shapes; check anyway.
    body = header[start:end]
    if body.count('"') % 2:
        raise ValueError("unbalanced quotes before the first `;`")
    return "".join(unescape(m.group(1)) for m in LITERAL.finditer(body))


def slim(text: str, keep_uv: bool = False) -> str:
    """Drops vn lines and normal indices of face corners, and unless
    `keep_uv` vt lines and texture indices too."""
    drop = ("vn",) if keep_uv else ("vt", "vn")
    parts = 2 if keep_uv else 1
    lines = []
    for line in text.splitlines():
        words = line.split()
        if words and words[0] in drop:
            continue
        if words and words[0] == "f":
            line = "f " + " ".join("/".join(w.split("/")[:parts]) for w in words[1:])
        lines.append(line.rstrip())
    return "\n".join(lines).rstrip() + "\n"


def shapes(src: pathlib.Path, rev: str):
    """(name, header text) of every catmark shape, sorted by name."""
    tree = src / "regression" / "shapes"
    if tree.is_dir():
        for path in sorted(tree.glob("catmark_*.h")):
            yield path.stem, path.read_text()
        return
    git = ["git", f"--git-dir={src}"]
    names = subprocess.run(
        git + ["ls-tree", "--name-only", rev, "regression/shapes/"],
        check=True, capture_output=True, text=True).stdout.split()
    for path in sorted(n for n in names if re.search(r"/catmark_[^/]*\.h$", n)):
        text = subprocess.run(git + ["show", f"{rev}:{path}"], check=True,
                              capture_output=True, text=True).stdout
        yield pathlib.Path(path).stem, text


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("opensubdiv", type=pathlib.Path)
    ap.add_argument("out", type=pathlib.Path)
    ap.add_argument("--rev", default="HEAD")
    ap.add_argument("--keep-uv", action="store_true",
                    help="keep texture coordinates (vt lines, v/vt corners)")
    ap.add_argument("--only", default="",
                    help="only the shapes whose name holds this")
    args = ap.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    count = 0
    for name, header in shapes(args.opensubdiv, args.rev):
        if args.only not in name:
            continue
        try:
            text = slim(obj_text(header, name), args.keep_uv)
        except ValueError as e:
            print(f"{name}: {e}", file=sys.stderr)
            return 1
        (args.out / f"{name}.obj").write_text(text)
        faces = sum(1 for l in text.splitlines() if l.startswith("f "))
        print(f"{name}.obj: {faces} faces")
        count += 1
    if count == 0:
        print(f"no regression/shapes/catmark_*.h under {args.opensubdiv}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
