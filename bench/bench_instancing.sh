#!/usr/bin/env bash
# Benchmark (not a test): EXT_mesh_gpu_instancing against the same triangles written out as one
# mesh (bench/make_instanced.py: N small 14-triangle huts scattered on a square), whole
# processes in turns: `rayfarm render` of a 24-frame turntable at 640x360 (default quality),
# alone (one process: its peak RSS is the whole memory). Prints each side's best wall seconds
# and peak RSS over REPEAT rounds and the ratios instanced / flattened (issue 42's aim: speed >=
# 0.8x the flattened file's, at a fraction of its memory).
#   [REPEAT=3] [N=10000] bash bench/bench_instancing.sh [BUILD_DIR]
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
bin=$build/bin/rayfarm
[ -x "$bin" ] || { echo "bench_instancing: $bin missing" >&2; exit 1; }
repeat=${REPEAT:-3}
n=${N:-10000}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python3 bench/make_instanced.py "$n" "$tmp/instanced.gltf"
python3 bench/make_instanced.py "$n" "$tmp/flat.gltf" --flatten

run() {  # instanced|flat -> "wall_s peak_kb"
  /usr/bin/time -f "%e %M" -o "$tmp/time" "$bin" render "$tmp/$1.gltf" --frames 0:23 --size 640x360 -o "$tmp/$1.mp4" \
    --no-frames 2> "$tmp/log" || { cat "$tmp/log" >&2; exit 1; }
  cat "$tmp/time"
}

echo "bench_instancing: $bin, N=$n instances ($((n * 14)) triangles), $(nproc) CPUs, load $(cut -d' ' -f1-3 /proc/loadavg), $repeat rounds in turns"
best_i=1e9 best_f=1e9 mem_i=0 mem_f=0
for r in $(seq "$repeat"); do
  read -r wi mi < <(run instanced)
  read -r wf mf < <(run flat)
  echo "  round $r: instanced $wi s, $((mi / 1024)) MiB; flattened $wf s, $((mf / 1024)) MiB"
  best_i=$(python3 -c "print(min($best_i, $wi))"); best_f=$(python3 -c "print(min($best_f, $wf))")
  mem_i=$mi mem_f=$mf
done
python3 -c "print('best: instanced %.2f s, flattened %.2f s: speed %.3fx the flattened file; memory %.3fx (%d / %d MiB)' % ($best_i, $best_f, $best_f / $best_i, $mem_i / $mem_f, $mem_i // 1024, $mem_f // 1024))"
