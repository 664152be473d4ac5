#!/usr/bin/env bash
# Benchmark (not a test): the interactive frame rate of `rayfarm view` while orbiting the
# 2CylinderEngine glTF model at 640x360, under Xvfb, the mouse driven by xdotool (XTEST).
# Prints the window's own --stats figures: frames shown, fps while moving, and the mean and p95
# latency from an input event to the first frame on screen that answers it.
#   bash bench/bench_view.sh [BUILD_DIR] [SECONDS]     (defaults: build, 8)
#   NP=3 bash bench/bench_view.sh                      the window under mpirun -np 3
# Targets: >= 30 fps while moving, p95 latency <= 50 ms.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
seconds=${2:-8}
RAYFARM_BIN=$build/bin/rayfarm
source examples/common.sh
engine=/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb
tmp=$(mktemp -d)
Xvfb -displayfd 3 -screen 0 1600x900x24 -nolisten tcp 3>"$tmp/display" 2>"$tmp/xvfb.log" &
xvfb=$!
view=
trap '[ -n "$view" ] && kill $view 2>/dev/null; kill $xvfb 2>/dev/null; wait 2>/dev/null; rm -rf "$tmp"' EXIT
for _ in $(seq 50); do [ -s "$tmp/display" ] && break; sleep 0.1; done
export DISPLAY=:$(tr -dc 0-9 <"$tmp/display")
# Wait until the server answers a client: a window started earlier may fail to connect.
for _ in $(seq 50); do xdotool getdisplaygeometry >/dev/null 2>&1 && break; sleep 0.1; done

launch=()
[ -n "${NP:-}" ] && launch=(mpirun --oversubscribe -np "$NP")
"${launch[@]}" "$bin" view "$engine" --size 640x360 --stats "$tmp/stats.json" 2>"$tmp/view.log" &
view=$!
wid=
for _ in $(seq 100); do wid=$(xdotool search --name '^rayfarm view' 2>/dev/null | head -1 || true); [ -n "$wid" ] && break; sleep 0.2; done
[ -n "$wid" ] || { echo "bench_view: no window: $(cat "$tmp/view.log")" >&2; exit 1; }
sleep 3  # the first picture at rest

# One xdotool process plays the whole drag: a 4-pixel step every 16 ms (a 60 Hz mouse).
steps=$((seconds * 1000 / 16))
cmd=(mousemove --window "$wid" 120 180 mousedown 1)
for i in $(seq "$steps"); do cmd+=(mousemove_relative -- 4 0 sleep 0.016); done
cmd+=(mouseup 1)
load_before=$(cut -d' ' -f1-3 /proc/loadavg)
xdotool "${cmd[@]}"
load_after=$(cut -d' ' -f1-3 /proc/loadavg)
sleep 1
xdotool windowfocus --sync "$wid" key ctrl+q
wait $view
view=

echo "bench_view: $(nproc) CPUs, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //')"
echo "bench_view: load before/after the drag: $load_before / $load_after (other processes share these cores)"
python3 - "$tmp/stats.json" "$seconds" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
print(f"2CylinderEngine.glb 640x360, {sys.argv[2]} s orbit drag, {s['ranks']} rank x {s['threads_per_rank']} threads:")
print(f"  frames shown {s['frames_shown']} ({s['moving_frames']} while moving)")
by_w = ", ".join(f"{n} at {w}x{int(w) * 9 // 16}" for w, n in sorted(s["moving_frames_by_width"].items(), key=lambda x: -int(x[0])))
print(f"  moving frames by rendered size: {by_w} (1 spp; shown scaled to 640x360)")
print(f"  fps while moving {s['moving_fps']:.1f}   (target >= 30)")
print(f"  input -> display latency: mean {s['latency_mean_ms']:.1f} ms, p95 {s['latency_p95_ms']:.1f} ms over {s['latency_samples']} frames   (target p95 <= 50)")
PY
