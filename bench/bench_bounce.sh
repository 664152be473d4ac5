#!/usr/bin/env bash
# Benchmark (not a test): what the default look's bounce light costs, as whole processes.
#   [REPEAT=5] bash bench/bench_bounce.sh BUILD_DIR [BASE_BUILD_DIR]
# With one build, its default look against the same binary with --bounce 0; with two, BUILD_DIR
# against BASE_BUILD_DIR (say, a build of the commit before the bounce light) at their defaults.
# Cases, each run REPEAT times, all cases and both sides in turns within a round (the host is
# shared: a run only ever loses time to a neighbour, so each keeps its fastest):
# - pbr_grid lights only and with studio.exr: `rayfarm still scenes/pbr_grid/pbr_grid.gltf
#   --camera 0 [--environment studio.exr]` (default settings: 4 spp, auto exposure), wall seconds;
# - 2CylinderEngine's default turntable at --spp 1, 640x360, 120 frames, mpirun -np 2 in frame
#   and pixel mode, --no-frames: sustained fps from --stats (bench_farm.sh's engine case).
# Prints a table of best times, and the ratio of each case to its base.
set -euo pipefail
cd "$(dirname "$0")/.."
new=${1:?usage: bench_bounce.sh BUILD_DIR [BASE_BUILD_DIR]}
base=${2:-}
repeat=${REPEAT:-5}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 HWLOC_COMPONENTS=-gl
engine=/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# side: "new" or "base"; prints the binary and the extra arguments of that side.
binary() { if [ "$1" = new ] || [ -z "$base" ]; then echo "$new/bin/rayfarm"; else echo "$base/bin/rayfarm"; fi; }
extra() { if [ "$1" = base ] && [ -z "$base" ]; then echo "--bounce 0"; fi; }

still() {  # side name args...
  local side=$1 name=$2
  shift 2
  local t0=$EPOCHREALTIME
  # shellcheck disable=SC2046
  "$(binary "$side")" still scenes/pbr_grid/pbr_grid.gltf --camera 0 "$@" $(extra "$side") -o "$tmp/$side.$name.png" 2>/dev/null
  echo "$side $name $t0 $EPOCHREALTIME" >> "$tmp/times"
}

film() {  # side mode
  local side=$1 mode=$2
  # shellcheck disable=SC2046
  mpirun --oversubscribe -np 2 "$(binary "$side")" render "$engine" --spp 1 --size 640x360 --mode "$mode" --no-frames \
    $(extra "$side") -o "$tmp/$side.$mode.mp4" --stats "$tmp/$side.$mode.json" 2>/dev/null
  rm -f "$tmp/$side.$mode.mp4"
  echo "$side engine_$mode 0 $(python3 -c "import json,sys; print(1.0/json.load(open(sys.argv[1]))['sustained_fps'])" "$tmp/$side.$mode.json")" >> "$tmp/times"
}

echo "bench_bounce: $(nproc) CPUs, load $(cut -d' ' -f1-3 /proc/loadavg)"
for ((round = 1; round <= repeat; round++)); do
  for side in base new; do
    still "$side" lights
    still "$side" studio --environment scenes/environments/studio.exr
    film "$side" frame
    film "$side" pixel
  done
  echo "bench_bounce: round $round of $repeat done, load $(cut -d' ' -f1-3 /proc/loadavg)"
done
python3 - "$tmp/times" <<'PY'
import sys
best = {}
for line in open(sys.argv[1]):
    side, name, t0, t1 = line.split()
    best[(side, name)] = min(best.get((side, name), 1e30), float(t1) - float(t0))
print("| case | base | new | new / base |")
print("| --- | ---: | ---: | ---: |")
for name in ["lights", "studio", "engine_frame", "engine_pixel"]:
    b, n = best[("base", name)], best[("new", name)]
    if name.startswith("engine"):  # stored as seconds a frame: show fps
        print(f"| {name} (fps, --spp 1, 2 ranks) | {1 / b:.2f} | {1 / n:.2f} | {b / n:.2f}x fps |")
    else:
        print(f"| pbr_grid still {name} (s) | {b:.3f} | {n:.3f} | {n / b:.2f}x time |")
PY
