#!/bin/sh
# The animation demo as a picture sequence: `render --time` at N evenly
# spaced times of one loop of a scene's animation, then an animated PNG and
# a contact sheet of the frames (python3 with PIL).
#
#   tools/anim/sequence.sh [SCENE] [OUT_DIR] [FRAMES] [SIZE]
#
# Defaults: scenes/anim.toml, out/anim-sequence, 16 frames, 480x270.
# Extra render flags go in $RENDER_FLAGS (e.g. "--shade wedges").
set -eu
root=$(cd "$(dirname "$0")/../.." && pwd)
scene=${1:-scenes/anim.toml}
out=${2:-out/anim-sequence}
frames=${3:-16}
size=${4:-480x270}
cd "$root"
cargo build --release --quiet
mkdir -p "$out"
duration=$(python3 -c "import tomllib; print(tomllib.load(open('$scene','rb')).get('animation',{}).get('duration',4.0))")
k=0
while [ "$k" -lt "$frames" ]; do
    t=$(python3 -c "print(round($duration * $k / $frames, 6))")
    name=$(printf '%s/frame-%03d.png' "$out" "$k")
    # shellcheck disable=SC2086
    ./target/release/bezier-subdiv render --scene "$scene" --time "$t" --size "$size" \
        --warmup 0 --out "$name" ${RENDER_FLAGS:-} > /dev/null
    echo "$name: t = $t s"
    k=$((k + 1))
done
python3 - "$out" "$frames" "$duration" <<'PY'
import sys
from PIL import Image
out, n, duration = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
frames = [Image.open(f"{out}/frame-{k:03d}.png").convert("RGB") for k in range(n)]
frames[0].save(f"{out}/sequence.png", save_all=True, append_images=frames[1:],
               duration=int(1000 * duration / n), loop=0, optimize=True)
cols = 4
rows = (n + cols - 1) // cols
w, h = frames[0].size
sheet = Image.new("RGB", (cols * w, rows * h))
for k, f in enumerate(frames):
    sheet.paste(f, ((k % cols) * w, (k // cols) * h))
sheet.save(f"{out}/sheet.png", optimize=True)
print(f"wrote {out}/sequence.png (animated PNG, {n} frames) and {out}/sheet.png")
PY
