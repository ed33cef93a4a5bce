#!/usr/bin/env bash
# Issue 22's measurements, as Markdown tables on stdout (docs/BENCHMARKS.md,
# "Instances and culling"): scene memory; the cost of 10x more instances
# outside the frustum or behind an occluder; occlusion culling on and off
# along the kitchen's and the herd's keyframes. Every figure comes from
# `render --repeat N` stats files written under OUT (default out/culling).
#
# Usage: tools/bench/culling.sh [BIN] [OUT] [SIZE] [REPEAT]
#   BIN     the bezier-subdiv binary (default target/release/bezier-subdiv)
#   SIZE    image size (default 1920x1080)
#   REPEAT  timed frames per render, medians reported (default 3)
set -euo pipefail
cd "$(dirname "$0")/../.."
BIN=${1:-target/release/bezier-subdiv}
OUT=${2:-out/culling}
SIZE=${3:-1920x1080}
REPEAT=${4:-3}
mkdir -p "$OUT"

python3 tools/bench/extra_instances.py scenes/kitchen.toml "$OUT/outside.toml" \
  --copies 10 --offset 0 0 -2000
python3 tools/bench/extra_instances.py scenes/kitchen.toml "$OUT/hidden.toml" \
  --copies 10 --offset 0 65 0 --step 0 40 0

# render SCENE FRAME OCCLUSION TAG: one stats file OUT/TAG.json.
render() {
  "$BIN" render --scene "$1" --frame "$2" --occlusion "$3" --size "$SIZE" \
    --repeat "$REPEAT" --out "$OUT/$4.png" >/dev/null
}

fig() { # FILE KEY... : a figure of a stats file
  python3 -c '
import json, sys
d = json.load(open(sys.argv[1]))
for k in sys.argv[2].split("."):
    d = d.get(k, "-") if isinstance(d, dict) else "-"
print(d if not isinstance(d, float) else f"{d:.1f}")' "$1" "$2"
}

echo "### Scene memory"
echo
echo "| scene | base patches | model patches | instances | model patches + flags | shading patches | instance records, roots, visibility |"
echo "|---|---:|---:|---:|---:|---:|---:|"
for s in kitchen herd; do
  render "scenes/$s.toml" 0 on "mem-$s"
  f="$OUT/mem-$s.json"
  echo "| $s | $(fig "$f" patches) | $(fig "$f" model_patches) | $(fig "$f" instances) | $(fig "$f" memory_bytes.base_patches) | $(fig "$f" memory_bytes.shading_patches) | $(fig "$f" memory_bytes.instances) |"
done
echo

echo "### Cost follows what is seen (occlusion on, $SIZE, median of $REPEAT frames)"
echo
echo "| scene | keyframe | instances | triangles | GPU ms (frame) | subdivide | draw | instances culled / hidden |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|"
for case in "scenes/kitchen.toml 7 kitchen" "$OUT/outside.toml 7 outside" "$OUT/hidden.toml 7 hidden" \
            "scenes/kitchen.toml 0 kitchen" "$OUT/outside.toml 0 outside"; do
  set -- $case
  tag="cost-$3-$2"
  render "$1" "$2" on "$tag"
  f="$OUT/$tag.json"
  echo "| $3 | $2 | $(fig "$f" instances) | $(fig "$f" triangles) | $(fig "$f" gpu_ms.frame) | $(fig "$f" gpu_ms.subdivide) | $(fig "$f" gpu_ms.draw) | $(fig "$f" method_stats.instances_culled) / $(fig "$f" method_stats.instances_occluded) |"
done
echo

echo "### Occlusion culling on and off ($SIZE, median of $REPEAT frames)"
echo
echo "| scene | keyframe | triangles off | triangles on | ratio | GPU ms off | GPU ms on | instances hidden | nodes hidden |"
echo "|---|---:|---:|---:|---:|---:|---:|---:|---:|"
for case in "kitchen 0 1 2 3 4 5 6 7" "herd 0 1 2 3 4 5"; do
  set -- $case
  s=$1
  shift
  for k in "$@"; do
    render "scenes/$s.toml" "$k" off "occ-$s-$k-off"
    render "scenes/$s.toml" "$k" on "occ-$s-$k-on"
    a="$OUT/occ-$s-$k-off.json"
    b="$OUT/occ-$s-$k-on.json"
    ta=$(fig "$a" triangles)
    tb=$(fig "$b" triangles)
    echo "| $s | $k | $ta | $tb | $(python3 -c "print(f'{$tb/$ta:.3f}')") | $(fig "$a" gpu_ms.frame) | $(fig "$b" gpu_ms.frame) | $(fig "$b" method_stats.instances_occluded) | $(fig "$b" method_stats.occluded) |"
  done
done
