#!/usr/bin/env bash
# Benchmark (not a test): the ceiling of rank 0 (the coordinator) of `rayfarm render`, with
# near-free work, so that what is measured is rank 0's own work per frame: dispatch, gather,
# frame assembly, PNG frames and the video. Since issue 32 the chunks are encoded on the other
# ranks and rank 0 only joins them: in frame mode by the rank that renders the chunk's frames, in pixel
# mode by the rank that assembled it from every rank's tiles (rank 0 then only schedules tiles
# and reads a note per tile). MODES="frame pixel" as before; run the same script from a
# checkout before the change for its "before" figures. Whole `mpirun` processes of
# scenes/bench/all_miss.json (a camera looking away from a tiny sphere), with
# RAYFARM_BENCH_FREE_WORK=1 in every rank's environment: a stand-in renderer plugged into the
# ranks' engines (farm/cluster/bench_free_work.h) that fills each work item with a cheap pattern
# moving with the frame instead of tracing it (even all-miss rays cost about 35 ns a pixel, which
# would make two workers the bottleneck at 4K, not rank 0).
#   [NP=3] [FRAMES_SCALE=1] [REPEAT=1] [CHUNK=12] [MODES="frame pixel"] bash bench/bench_coordinator.sh [BUILD_DIR]
#   (default: build-bench, configured with -DRAYFARM_BENCH_HOOKS=ON: the stand-in renderer is
#   compiled only into such a build, never into the default one)
# NP=3 is rank 0 coordinating only (with three ranks or more it renders nothing) and two worker
# ranks. Sizes 640x360, 1920x1080 and 3840x2160, pixel and frame mode, PNG frames kept (the
# default) and not (--no-frames): 12 runs of 120/60/24 frames, a few minutes on 2 cores;
# FRAMES_SCALE=4 runs four times as many frames, REPEAT=N every configuration N times in turns
# (the table keeps each configuration's best run). Printed per run: frames/s and work items
# (tiles)/s rank 0 sustained (first dispatch to last frame muxed), rank 0's CPU (getrusage of
# its process, in cores over the sustained window and ms a frame), the busy shares of rank 0's
# video thread (joining chunks; encoding, for a GIF or an older build) and PNG writer from the
# --stats file, who encoded, and the load average at the start of the run.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build-bench}
bin=$build/bin/rayfarm
# A rayfarm without the stand-in (a default build) would trace every pixel and measure its
# workers instead of rank 0: configure BUILD_DIR with the hooks and build it.
if [ ! -x "$bin" ] || ! grep -q RAYFARM_BENCH_FREE_WORK "$bin"; then
  bash tests/install-deps.sh
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DRAYFARM_BENCH_HOOKS=ON >/dev/null
  cmake --build "$build" -j"$(nproc 2>/dev/null || echo 2)" --target rayfarm
  grep -q RAYFARM_BENCH_FREE_WORK "$bin" || { echo "bench_coordinator: $bin has no benchmark hooks" >&2; exit 1; }
fi
bin=$(realpath "$bin")
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
np=${NP:-3}
scale=${FRAMES_SCALE:-1}
repeat=${REPEAT:-1}
# Chunks of 12 frames (CHUNK=N), so that even the 24 frames at 4K make a chunk for each worker
# in frame mode; pixel mode's file is the same.
chunk=${CHUNK:-12}
modes=${MODES:-frame pixel}
scene=$(realpath scenes/bench/all_miss.json)
tmp=$(mktemp -d)
trap '[ -n "${KEEP_TMP:-}" ] || rm -rf "$tmp"' EXIT
# Rank 0 runs under bash so that `times` can give its process's CPU (user and system) at the end.
cat > "$tmp/rank0cpu.sh" <<'SH'
#!/usr/bin/env bash
out=$1; shift
if [ "${OMPI_COMM_WORLD_RANK:-0}" = 0 ]; then
  "$@"; rc=$?
  times > "$out"  # line 2: its children's user and system CPU (not in a pipe: a subshell has none)
  exit $rc
fi
exec "$@"
SH

run() {  # name size frames mode [--no-frames]
  local name=$1 size=$2 frames=$3 mode=$4
  shift 4
  cut -d' ' -f1-3 /proc/loadavg > "$tmp/$name.load"
  rm -rf "$tmp/$name.mp4" "$tmp/$name.mp4.frames"
  mpirun --oversubscribe -np "$np" -x RAYFARM_BENCH_FREE_WORK=1 bash "$tmp/rank0cpu.sh" "$tmp/$name.cpu" \
    "$bin" render "$scene" -o "$tmp/$name.mp4" --mode "$mode" --size "$size" --frames "0:$((frames - 1))" \
    --stats "$tmp/$name.json" --chunk-frames "$chunk" "$@" 2> "$tmp/$name.log" || { cat "$tmp/$name.log" >&2; exit 1; }
  rm -rf "$tmp/$name.mp4" "$tmp/$name.mp4.frames"  # 4K PNG frames are large; keep the disk free
}

echo "bench_coordinator: $(nproc) CPUs, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'), mpirun -np $np, load $(cut -d' ' -f1-3 /proc/loadavg)"
for ((round = 1; round <= repeat; round++)); do
  for size in 640x360 1920x1080 3840x2160; do
    case $size in 640x360) n=120 ;; 1920x1080) n=60 ;; *) n=24 ;; esac
    n=$((n * scale))
    for mode in $modes; do
      run "${size}_${mode}_png.r$round" "$size" "$n" "$mode"
      run "${size}_${mode}_nofr.r$round" "$size" "$n" "$mode" --no-frames
    done
  done
  echo "bench_coordinator: round $round of $repeat done, load $(cut -d' ' -f1-3 /proc/loadavg)"
done

python3 - "$tmp" "$repeat" "$modes" <<'PY'
import json, os, re, sys
d, repeat, modes = sys.argv[1], int(sys.argv[2]), sys.argv[3].split()
def secs(t):  # bash `times`: 0m2.901s
    m = re.match(r"(\d+)m([\d.]+)s", t)
    return int(m.group(1)) * 60 + float(m.group(2))
def one(name):
    j = json.load(open(os.path.join(d, name + ".json")))
    u, s = open(os.path.join(d, name + ".cpu")).read().splitlines()[1].split()
    j["cpu0"] = secs(u) + secs(s)
    j["load"] = open(os.path.join(d, name + ".load")).read().strip()
    return j
print(f"best of {repeat} run(s) per configuration; rank 0 CPU is its whole process (load, start-up included)")
print(f"{'size':>10} {'mode':6}{'PNG':>5}{'frames':>7}{'frames/s':>10}{'items/s':>10}{'rank0 cores':>12}"
      f"{'rank0 ms/fr':>12}{'r0 video':>9}{'PNG wr.':>9}  encoded by   load at start")
for size in ("640x360", "1920x1080", "3840x2160"):
    for mode in modes:
        for png in ("png", "nofr"):
            runs = [one(f"{size}_{mode}_{png}.r{k}") for k in range(1, repeat + 1)]
            j = max(runs, key=lambda r: r["sustained_fps"])
            t = j["render_s"]
            items = sum(r["tiles"] if mode == "pixel" else r["frames"] for r in j["per_rank"])
            print(f"{size:>10} {mode:6}{'yes' if png == 'png' else 'no':>5}{j['frames']:7}{j['sustained_fps']:10.2f}"
                  f"{items / t:10.0f}{j['cpu0'] / t:12.2f}{1000 * j['cpu0'] / j['frames']:12.1f}"
                  f"{100 * j.get('mux_s', j['encode_s']) / t:8.0f}%{100 * j['png_s'] / t:8.0f}%  "
                  f"{'ranks' if j.get('chunks_encoded_by', 'rank 0') != 'rank 0' else 'rank 0':11}  {j['load']}")
PY
echo "bench_coordinator: load afterwards $(cut -d' ' -f1-3 /proc/loadavg)"
