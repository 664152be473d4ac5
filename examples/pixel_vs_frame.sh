#!/usr/bin/env bash
# The same job in pixel mode (tiles of every frame shared out) and in frame mode (whole frames
# shared out), with their statistics side by side.
#   bash examples/pixel_vs_frame.sh [SCENE] [RANKS]      (default: scenes/whitted.json, 2)
set -euo pipefail
cd "$(dirname "$0")/.."
scene=${1:-scenes/whitted.json}
ranks=${2:-2}
source examples/common.sh
mkdir -p out
for mode in pixel frame; do
  mpirun --oversubscribe -np "$ranks" "$bin" render "$scene" -o "out/pvf_$mode.mp4" --mode "$mode" --size 640x360 \
    --no-frames --stats "out/pvf_$mode.json"
done
python3 - out/pvf_pixel.json out/pvf_frame.json <<'PY'
import json, sys
p, f = (json.load(open(a)) for a in sys.argv[1:3])
rows = [("frames", "frames"), ("ranks", "ranks"), ("threads per rank", "threads_per_rank"),
        ("sustained fps", "sustained_fps"), ("wall s", "wall_s"), ("render span s", "render_s"),
        ("encoder busy s", "encode_s"), ("encoder share", "encoder_share"), ("rays total", None)]
print(f"{'':18}{'pixel':>14}{'frame':>14}")
for name, key in rows:
    a, b = (s["rays"]["total"] if key is None else s[key] for s in (p, f))
    fmt = (lambda v: f"{v:14.3f}") if isinstance(a, float) else (lambda v: f"{v:14}")
    print(f"{name:18}{fmt(a)}{fmt(b)}")
for s, mode in ((p, "pixel"), (f, "frame")):
    work = ", ".join(f"rank {r['rank']}: {r['busy_s']:.2f} s busy, {r['tiles'] if mode == 'pixel' else r['frames']} {'tiles' if mode == 'pixel' else 'frames'}" for r in s["per_rank"])
    print(f"{mode}: {work}")
PY
