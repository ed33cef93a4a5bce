#!/bin/sh
# The peer check of the animation's stencil tables (docs/BENCHMARKS.md,
# "Animation"): OpenSubdiv 3.5's StencilTable::UpdateValues per frame on
# the car and pawn cages (feature-adaptive at isolation 0, 2 and 3, Gregory
# end caps), and this project's update pass on the same cages deforming
# (render --repeat, gpu_ms.update), with the bytes per patch of both
# tables.
#
#   tools/osd-stencils/run.sh            # needs g++ and Debian's libosd-dev
#
# Set SIZE (default 320x180) and REPEAT (default 20) to change the render.
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
tool=$(mktemp -d)
trap 'rm -rf "$tool"' EXIT
g++ -O2 -std=c++17 -o "$tool/osd_stencils" "$root/tools/osd-stencils/osd_stencils.cpp" -losdCPU
size=${SIZE:-320x180}
repeat=${REPEAT:-20}
cd "$root"
cargo build --release --quiet
for m in car pawn; do
    for iso in 0 2 3; do
        "$tool/osd_stencils" "scenes/models/catmark_$m.obj" --isolation "$iso"
    done
    ./target/release/bezier-subdiv render --scene "tools/osd-stencils/$m.toml" --time 1 \
        --size "$size" --repeat "$repeat" --out "$tool/$m.png" > /dev/null
    python3 - "$tool/$m.json" "$m" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
a, ms = d["animation"], d["gpu_ms"]
print(f"ours {sys.argv[2]}: {a['patches']} patches, {a['vertices']} cage vertices, "
      f"update {ms['update']:.4f} ms median of {d['repeat']} "
      f"(min {d['gpu_ms_min']['update']:.4f}, max {d['gpu_ms_max']['update']:.4f}), "
      f"subdivide {ms.get('subdivide', 0):.4f} ms, frame {ms['frame']:.4f} ms; "
      f"animation buffers {d['memory_bytes']['animation']} bytes on {d['device']}")
PY
done
