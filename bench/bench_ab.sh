#!/usr/bin/env bash
# Benchmark (not a test): two builds of rayfarm on the same static work, whole processes in
# turns, to see whether a change made a scene that does not move any slower. Per case, each
# build's best sustained fps over REPEAT rounds (other work on a shared machine only ever slows a
# run down) and their ratio B / A:
#   whitted    scenes/whitted.json, 31 frames 640x360 --spp 1, one process (bench_whitted's film)
#   engine     the 2CylinderEngine turntable, 120 frames 640x360 --spp 1, mpirun -np 2 frame mode
#              (bench_farm's film)
#   close      scenes/bench/engine_close.json, 40 frames 640x360, 1 thread (bench_embree's rayfarm side)
#   walker     a skinned film, for comparison: tests/reference/characters/walker.gltf, 120 frames
#              640x360, default quality, mpirun -np 2
#   [REPEAT=3] bash bench/bench_ab.sh BUILD_A BUILD_B
set -euo pipefail
cd "$(dirname "$0")/.."
a=$1 b=$2
for d in "$a" "$b"; do [ -x "$d/bin/rayfarm" ] || { echo "bench_ab: $d/bin/rayfarm missing" >&2; exit 1; }; done
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 HWLOC_COMPONENTS=-gl
repeat=${REPEAT:-3}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
engine=/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb

run() {  # build case -> sustained fps
  local bin=$1/bin/rayfarm
  case $2 in
    whitted) "$bin" render scenes/whitted.json -o "$tmp/o.mp4" --no-frames --size 640x360 --spp 1 --stats "$tmp/s.json" 2>"$tmp/log" ;;
    engine) mpirun --oversubscribe -np 2 "$bin" render "$engine" -o "$tmp/o.mp4" --no-frames --size 640x360 --spp 1 --mode frame \
              --stats "$tmp/s.json" 2>"$tmp/log" ;;
    close) "$bin" render scenes/bench/engine_close.json -o "$tmp/o.mp4" --no-frames --threads 1 --stats "$tmp/s.json" 2>"$tmp/log" ;;
    walker) mpirun --oversubscribe -np 2 "$bin" render tests/reference/characters/walker.gltf -o "$tmp/o.mp4" --no-frames \
              --size 640x360 --stats "$tmp/s.json" 2>"$tmp/log" ;;
  esac || { cat "$tmp/log" >&2; exit 1; }
  python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['sustained_fps'])" "$tmp/s.json"
}

echo "bench_ab: A=$a B=$b, $(nproc) CPUs, load $(cut -d' ' -f1-3 /proc/loadavg), $repeat rounds in turns"
for c in whitted engine close walker; do
  best_a=0 best_b=0
  for r in $(seq "$repeat"); do
    fa=$(run "$a" $c); fb=$(run "$b" $c)
    echo "  $c round $r: A $fa fps, B $fb fps"
    best_a=$(python3 -c "print(max($best_a, $fa))"); best_b=$(python3 -c "print(max($best_b, $fb))")
  done
  python3 -c "import sys; a, b = $best_a, $best_b; print(f'{sys.argv[1]}: best A {a:.2f} fps, B {b:.2f} fps, B/A {b / a:.3f}')" "$c"
done
echo "bench_ab: load at the end $(cut -d' ' -f1-3 /proc/loadavg)"
