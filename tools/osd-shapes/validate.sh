#!/bin/sh
# Imports and validates every OpenSubdiv regression shape in
# tests/data/osd-shapes/ (extracted by tools/osd-shapes/extract.py): each
# cage gets a scene of its own, one-sided, seen from outside its bounding
# box, and goes through `import` and `validate` (oracle checks on the scene
# camera, the hole test from six cameras around it). Prints one line per
# shape: patches, the hole test's line, and the verdict.
#
#   tools/osd-shapes/validate.sh [OUT_DIR] [EXTRA VALIDATE FLAGS...]
#
# OUT_DIR (default: a fresh temporary directory) receives the scenes and
# each shape's import and validate output. Needs a release build
# (BEZIER_SUBDIV=path names another binary).
set -u
root=$(cd "$(dirname "$0")/../.." && pwd)
bin=${BEZIER_SUBDIV:-"$root/target/release/bezier-subdiv"}
out=${1:-$(mktemp -d)}
[ $# -gt 0 ] && shift
mkdir -p "$out"
fail=0
for obj in "$root"/tests/data/osd-shapes/catmark_*.obj; do
    name=$(basename "$obj" .obj)
    # The camera: outside the bounding box, looking at its centre.
    cam=$(awk '$1 == "v" {
            for (i = 0; i < 3; i++) {
                c = $(i + 2) + 0
                if (n == 0 || c < lo[i]) lo[i] = c
                if (n == 0 || c > hi[i]) hi[i] = c
            }
            n++
        }
        END {
            for (i = 0; i < 3; i++) m[i] = (lo[i] + hi[i]) / 2
            d = sqrt((hi[0]-lo[0])^2 + (hi[1]-lo[1])^2 + (hi[2]-lo[2])^2)
            if (d == 0) d = 1
            printf "position = [%g, %g, %g]\ntarget = [%g, %g, %g]\nnear = %g\nfar = %g\n",
                m[0] + 0.9*d, m[1] - 1.2*d, m[2] + 0.8*d, m[0], m[1], m[2], d/100, d*100
        }' "$obj")
    cat > "$out/$name.toml" <<EOF
name = "$name"
[camera]
$cam
[[model]]
name = "$name"
file = "$obj"
EOF
    "$bin" import "$obj" > "$out/$name.import.txt" 2>&1
    patches=$(awk '$1 == "patches" && $2 ~ /^[0-9,]+$/ {print $2; exit}' "$out/$name.import.txt")
    if "$bin" validate --scene "$out/$name.toml" --size 320x180 "$@" > "$out/$name.validate.txt" 2>&1; then
        verdict=ok
    else
        verdict=FAIL
        fail=$((fail + 1))
    fi
    holes=$(grep '^holes ' "$out/$name.validate.txt" | sed 's/  */ /g' | cut -d' ' -f5-)
    printf '%-28s %7s  %-4s %s\n' "$name" "${patches:-?}" "$verdict" "$holes"
done
echo "$fail failed; outputs in $out"
[ "$fail" -eq 0 ]
