#!/usr/bin/env bash
# Runs the README's commands in its order, as a new user does on a fresh
# machine, and prints how long each took: the figures the README quotes.
# The suite checks each mechanism on small cases (tests/cli.rs,
# tests/renderer.rs); this runs the full-size commands, which take minutes
# on a 2-core lavapipe, so it is a script and not a test.
#
#   tools/readme/run.sh [--cold] [--no-bench] [OUTDIR]
#
# --cold      disables Mesa's shader cache (MESA_SHADER_CACHE_DISABLE), so
#             every command compiles its shaders as on a fresh machine
# --no-bench  skips the README's bench command (about 25 minutes there)
# OUTDIR      where the images and stats go (default out/readme)
#
# Exits non-zero at the first command that fails.
set -euo pipefail
cd "$(dirname "$0")/../.."

bench=1
out=out/readme
for a in "$@"; do
  case "$a" in
    --cold) export MESA_SHADER_CACHE_DISABLE=true ;;
    --no-bench) bench=0 ;;
    -h|--help) sed -n 2,15p "$0"; exit 0 ;;
    -*) echo "unknown option $a (see --help)" >&2; exit 2 ;;
    *) out=$a ;;
  esac
done

cargo build --release -q
bin=target/release/bezier-subdiv
mkdir -p "$out"

step() {
  local name=$1; shift
  local start end
  start=$(date +%s.%N)
  "$bin" "$@"
  end=$(date +%s.%N)
  printf '== %-28s %6.1f s: bezier-subdiv %s\n' "$name" "$(echo "$end - $start" | bc)" "$*" \
    | tee -a "$out/times.txt"
}

: > "$out/times.txt"
step render render --out "$out/kitchen.png"
step ground-truth render --method ground-truth --grid 16 --out "$out/kitchen-gt.png"
step tess-flip render --method tess --flip --out "$out/kitchen-tess.png"
step validate validate
if [ "$bench" = 1 ]; then
  step bench bench --size 640x360 --frames 60 --grid 32 --out "$out/bench-kitchen"
fi
echo "times in $out/times.txt"
