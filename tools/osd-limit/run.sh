#!/bin/sh
# Regenerates tests/data/osd/*.txt: OpenSubdiv 3.5's limit surface at chosen
# points of the test cages, which tests/osd_reference.rs compares the cage
# converter against (so the tests need no OpenSubdiv).
#
#   tools/osd-limit/run.sh            # needs g++ and Debian's libosd-dev
#
# Each case: NAME MODEL BOUNDARY CREASES SAMPLES
#   BOUNDARY  none | edge-only | edge-and-corner | tag (the file's own tag,
#             else the converter's default, edge-and-corner)
#   CREASES   keep, or a number every `t crease` sharpness is replaced by
#   SAMPLES   grid (5x5 per face, edges included), nine (3x3), four,
#             dense (17x17), corners:M, rings:M (the irregular rings of isolation down to level M;
#             see osd_limit.cpp)
#   ISOLATE   optional: the `isolate` levels the test imports the case at,
#             e.g. 0/2/4 (default 0)
# The case line is written as the file's first line; the test reads it back.
#
# Then every catmark_* regression shape of OpenSubdiv's (tests/data/osd-shapes,
# extracted by tools/osd-shapes/extract.py) goes to tests/data/osd/shapes/,
# at its own tags, with as many samples per face as keeps the file small.
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
tool=$(mktemp -d)
trap 'rm -rf "$tool"' EXIT
g++ -O2 -std=c++17 -o "$tool/osd_limit" "$root/tools/osd-limit/osd_limit.cpp" -losdCPU
out="$root/tests/data/osd"
mkdir -p "$out"

run() {
    name=$1 model=$2 boundary=$3 creases=$4 samples=$5 isolate=${6:-0} dir=${7:-$out} fvar=${8:-}
    src="$root/$model"
    if [ "$creases" != keep ]; then
        # Same rewrite as the test: the last word of each crease line.
        awk -v s="$creases" '$1 == "t" && $2 == "crease" { $NF = s } { print }' "$src" > "$tool/cage.obj"
        src="$tool/cage.obj"
    fi
    opt=
    if [ "$boundary" != tag ]; then opt="--boundary $boundary"; else opt="--boundary edge-and-corner"; fi
    head="# case $name model=$model boundary=$boundary creases=$creases samples=$samples isolate=$isolate"
    if [ -n "$fvar" ]; then opt="$opt --fvar $fvar"; head="$head fvar=$fvar"; fi
    {
        echo "$head"
        # shellcheck disable=SC2086
        "$tool/osd_limit" "$src" $opt --samples "$samples" | grep -v '^#'
    } > "$dir/$name.txt"
    echo "$dir/$name.txt: $(wc -l < "$dir/$name.txt") lines"
}

run torus            scenes/models/catmark_torus.obj          tag             keep grid
run cube             scenes/models/catmark_cube.obj           tag             keep grid
run helmet           scenes/models/catmark_helmet.obj         tag             keep grid
run helmet_sharp     scenes/models/catmark_helmet.obj         tag             10   grid
run xord_interior    scenes/models/catmark_xord_interior.obj  tag             keep grid
run pole64           scenes/models/catmark_pole64.obj         tag             keep nine
run pawn             scenes/models/catmark_pawn.obj           tag             keep four
run car              scenes/models/catmark_car.obj            tag             keep four
run car_sharp        scenes/models/catmark_car.obj            tag             10   four
run grid_crease      tests/data/cages/grid_crease.obj         edge-and-corner keep grid
run grid_crease_edge tests/data/cages/grid_crease.obj         edge-only       keep grid
run grid_crease_none tests/data/cages/grid_crease.obj         none            keep grid
run grid_semi        tests/data/cages/grid_semi.obj           tag             keep grid
run book             tests/data/cages/book.obj                edge-and-corner keep grid
run cubes_touching   tests/data/cages/cubes_touching.obj      edge-and-corner keep grid

# Isolation: the irregular rings sampled down to level 4 or 5, imported at
# isolate 0 to 4.
run iso_xord_interior scenes/models/catmark_xord_interior.obj tag keep corners:4 0/1/2/3/4
run iso_pole64        scenes/models/catmark_pole64.obj        tag keep corners:4 0/1/2/3/4
run iso_cube          scenes/models/catmark_cube.obj          tag keep corners:5 0/1/2/3/4
run iso_grid_semi     tests/data/cages/grid_semi.obj          tag keep corners:4 0/1/2/3/4
# A Chaikin crease sharper (5) than the deepest level: still fitted there.
run iso_chaikin0      tests/data/osd-shapes/catmark_chaikin0.obj tag keep corners:4 0/1/2/3/4

# Fitted patches between the quarters: a fitted cubic's largest error lies
# between the 5x5 grid's samples (tests/osd_reference.rs,
# `fitted_patches_between_the_quarters`).
dense="$out/dense"
mkdir -p "$dense"
# Imported at isolate 0 and at the ceiling of the sharpest crease (5 for
# chaikin0 would take the test too long).
for shape in catmark_dart_edgeonly:0/2 catmark_cube_corner3:0/3 \
    catmark_pyramid_creases1:0/4 catmark_chaikin0:0; do
    name=${shape%:*}
    run "$name" "tests/data/osd-shapes/$name.obj" tag keep dense "${shape#*:}" "$dense"
done
# The irregular rings between their quarters (iso_cube's with 9x9 grids).
run catmark_cube_rings scenes/models/catmark_cube.obj tag keep rings:5 0/1/2/3/4 "$dense"

shapes="$out/shapes"
mkdir -p "$shapes"
for obj in "$root"/tests/data/osd-shapes/catmark_*.obj; do
    name=$(basename "$obj" .obj)
    faces=$(grep -c '^f ' "$obj")
    if [ "$faces" -le 60 ]; then samples=grid
    elif [ "$faces" -le 300 ]; then samples=nine
    else samples=four
    fi
    run "$name" "tests/data/osd-shapes/$name.obj" tag keep "$samples" 0 "$shapes"
done

# Texture coordinates: OpenSubdiv's face-varying shapes, the scenes' cube,
# torus and helmet (its faces' own UV squares) and a seam-free warped layout
# (grid_uv) and a sheet with a hexagon and triangles across a seam
# (ngon_uv), under both rules; each line ends with the UV limit
# (tests/osd_reference.rs, `uv_patches_follow_opensubdivs_face_varying_limit`).
fvar_dir="$out/fvar"
mkdir -p "$fvar_dir"
for model in tests/data/osd-fvar/catmark_fvar_bound0.obj tests/data/osd-fvar/catmark_fvar_bound1.obj \
    tests/data/osd-fvar/catmark_fvar_bound2.obj tests/data/osd-fvar/catmark_fvar_bound3.obj \
    tests/data/osd-fvar/catmark_fvar_bound4.obj tests/data/osd-fvar/catmark_fvar_project0.obj \
    scenes/models/catmark_cube.obj scenes/models/catmark_torus.obj scenes/models/catmark_helmet.obj \
    tests/data/cages/grid_uv.obj tests/data/cages/ngon_uv.obj; do
    for rule in corners-only all; do
        run "$(basename "$model" .obj)_$rule" "$model" tag keep grid 0 "$fvar_dir" "$rule"
    done
done
