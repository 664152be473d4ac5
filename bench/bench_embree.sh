#!/usr/bin/env bash
# Benchmark (not a test): traversal on equal work against Embree 3. Both render the 40-frame
# turntable of scenes/bench/engine_close.json (the 2CylinderEngine fills the frame) and
# engine_far.json (twice as far) at 640x360: primary rays plus one shadow ray per hit towards one
# point light. rayfarm is timed as the whole `rayfarm render --no-frames` process (load, BVH,
# render, H.264 encode); Embree as the whole bench/embree_bench process (rayfarm's loader,
# Embree's build, rtcIntersect1/rtcOccluded1 on the same rays from rayfarm's camera). Prints both
# frame rates and rayfarm / Embree for both distances on 1 and 2 threads. rayfarm runs twice
# per round: on engine_*.json, shaded with the model's own glTF materials (the metallic-roughness
# BRDF and its split-sum table: more work per hit than Embree's Lambert), and on
# engine_*_lambert.json, the same rays in one Lambert material shaded as the harness shades
# them (interpolated normals where the harness takes the geometric one): there mainly the
# traversal, rayfarm's per-pixel work and its H.264 encode differ.
#   bash bench/bench_embree.sh [BUILD_DIR]       (default: build)
# Environment: REPEAT (default 2): Embree and the two rayfarm runs take turns this many times;
# each one's best run counts, since other work on a shared machine only ever slows a run down.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
repeat=${REPEAT:-2}
bash tests/install-deps.sh libembree-dev
if [ ! -x "$build/bin/embree_bench" ] || [ ! -x "$build/bin/rayfarm" ]; then
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DRAYFARM_BUILD_BENCH=ON >/dev/null
  cmake --build "$build" -j"$(nproc 2>/dev/null || echo 2)" --target rayfarm embree_bench >/dev/null
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
now() { date +%s.%N; }

echo "bench_embree: $(nproc) CPUs, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'), load $(cut -d' ' -f1-3 /proc/loadavg)"
printf '%-8s %-8s %12s %12s %12s %14s %14s   %s\n' distance threads "rf glTF fps" "rf Lamb fps" "embree fps" "glTF/embree" "Lambert/embree" "embree render loop alone"
rf_fps() {  # scene threads -> frames per second of the whole rayfarm process (40 frames)
  local a b
  a=$(now)
  "$build/bin/rayfarm" render "$1" -o "$tmp/o.mp4" --no-frames --threads "$2" 2>"$tmp/rf.log" \
    || { cat "$tmp/rf.log" >&2; exit 1; }
  b=$(now)
  awk -v n="$frames" -v a="$a" -v b="$b" 'BEGIN { printf "%.2f", n / (b - a) }'
}
best() { awk -v x="$1" -v y="$2" 'BEGIN { print (x > y) ? x : y }'; }
for dist in close far; do
  scene=scenes/bench/engine_$dist.json lambert=scenes/bench/engine_${dist}_lambert.json
  for threads in 1 2; do
    best_rf=0 best_lb=0 best_em=0 loop=""
    for ((i = 1; i <= repeat; i++)); do
      b=$(now)
      out=$("$build/bin/embree_bench" "$scene" --threads "$threads")
      c=$(now)
      frames=$(sed -n 's/^embree: \([0-9]*\) frames.*/\1/p' <<<"$out")
      em=$(awk -v n="$frames" -v a="$b" -v b="$c" 'BEGIN { printf "%.2f", n / (b - a) }')
      if awk -v x="$em" -v y="$best_em" 'BEGIN { exit !(x > y) }'; then best_em=$em; loop=$(sed -n 's/.*(\([0-9.]* fps\).*/\1/p' <<<"$out"); fi
      rf=$(rf_fps "$scene" "$threads")  # an assignment alone: set -e stops on a failed render
      lb=$(rf_fps "$lambert" "$threads")
      best_rf=$(best "$rf" "$best_rf") best_lb=$(best "$lb" "$best_lb")
    done
    printf '%-8s %-8s %12s %12s %12s %13.2fx %13.2fx   %s\n' "$dist" "$threads" "$best_rf" "$best_lb" "$best_em" \
      "$(awk -v x="$best_rf" -v y="$best_em" 'BEGIN { print x / y }')" "$(awk -v x="$best_lb" -v y="$best_em" 'BEGIN { print x / y }')" "$loop"
  done
done
echo "whole processes, best of $repeat each; load afterwards $(cut -d' ' -f1-3 /proc/loadavg)"
