#!/usr/bin/env bash
# Benchmark (not a test): the Whitted orbit, 31 frames at 640×360, depth 5, 1 spp on all local
# cores, made by rayfarm and by POV-Ray 3.7 on scenes/reference/whitted.pov with the command
# of docs/architecture.md. Both are timed as whole processes: `rayfarm render scenes/whitted.json -o
# w.mp4 --size 640x360 --spp 1 --frames 0:30` (start-up, load, render, PNG frames kept, H.264
# encode) against povray writing its PNG frames. Prints both frame rates and their ratio, and as
# a second line the engine alone (bench/whitted_bench: frames rendered, nothing written).
#   bash bench/bench_whitted.sh [BUILD_DIR]       (default: build)
# Environment: POV_FILE (default scenes/reference/whitted.pov), THREADS (default: nproc),
# REPEAT (default 3): the two renderers take turns this many times. On a shared machine a run can
# lose a third of its speed to other work, so the summary compares each one's best run (the least
# disturbed) and also gives the median of the per-round ratios.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
threads=${THREADS:-$(nproc 2>/dev/null || echo 2)}
pov=${POV_FILE:-scenes/reference/whitted.pov}
repeat=${REPEAT:-3}

# POV-Ray is only needed here, so it is installed here (not by the test set-up).
if ! command -v povray >/dev/null; then bash tests/install-deps.sh povray; fi
bash tests/install-deps.sh
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DRAYFARM_BUILD_BENCH=ON >/dev/null
cmake --build "$build" -j"$threads" --target whitted_bench rayfarm >/dev/null
[ -f "$pov" ] || { echo "bench_whitted: $pov not found (set POV_FILE)" >&2; exit 1; }

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cp "$pov" "$tmp/whitted.pov"
TIMEFORMAT="%U %S"
rounds=()   # "rf_fps rf_cpu_ms pov_fps pov_cpu_ms engine_fps" per round
echo "bench_whitted: $(nproc) CPUs, load $(cut -d' ' -f1-3 /proc/loadavg)"
for ((i = 1; i <= repeat; i++)); do
  out=$("$build/bin/whitted_bench" scenes/whitted.json --size 640x360 --frames 31 --depth 5 --threads "$threads")
  echo "round $i engine alone, $out"
  engine_fps=$(sed -n 's/.* \([0-9.]*\) fps.*/\1/p' <<<"$out")

  rm -rf "$tmp/w.mp4" "$tmp/w.mp4.frames"
  start=$(date +%s.%N)
  rf_cpu=$( { time "$build/bin/rayfarm" render scenes/whitted.json -o "$tmp/w.mp4" --size 640x360 --spp 1 --frames 0:30 \
              --threads "$threads" 2>"$tmp/rf.log"; } 2>&1 | awk '{ print $1 + $2 }') || { cat "$tmp/rf.log" >&2; exit 1; }
  end=$(date +%s.%N)
  frames=$(ls "$tmp"/w.mp4.frames/frame_*.png | wc -l)
  rf_fps=$(awk -v n="$frames" -v a="$start" -v b="$end" 'BEGIN { printf "%.2f", n / (b - a) }')
  rf_cpu=$(awk -v p="$rf_cpu" -v n="$frames" 'BEGIN { printf "%.1f", 1e3 * p / n }')
  echo "round $i rayfarm render: $frames frames to MP4 + PNG frames, whole process: $(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.3f", b - a }') s, $rf_fps fps, $rf_cpu ms CPU per frame ($(grep -o 'encoder busy.*' "$tmp/rf.log"))"

  rm -f "$tmp"/whitted*.png
  start=$(date +%s.%N)
  pov_cpu=$( { time (cd "$tmp" && povray +Iwhitted.pov +W640 +H360 -A +WT"$threads" +KFI0 +KFF30 +KI0 +KF1 -D >/dev/null 2>&1); } 2>&1 | awk '{ print $1 + $2 }')
  end=$(date +%s.%N)
  frames=$(ls "$tmp"/whitted*.png | wc -l)
  pov_fps=$(awk -v n="$frames" -v a="$start" -v b="$end" 'BEGIN { printf "%.2f", n / (b - a) }')
  pov_ms=$(awk -v p="$pov_cpu" -v n="$frames" 'BEGIN { printf "%.1f", 1e3 * p / n }')
  echo "round $i povray:  $frames frames 640x360, +WT$threads, no anti-aliasing: $(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.3f", b - a }') s, $pov_fps fps, $pov_ms ms CPU per frame"
  rounds+=("$rf_fps $rf_cpu $pov_fps $pov_ms $engine_fps")
done

printf '%s\n' "${rounds[@]}" | awk -v n="$repeat" '
  { rf[NR] = $1; rc[NR] = $2; pf[NR] = $3; pc[NR] = $4; ratio[NR] = $1 / $3
    if ($1 > brf) brf = $1; if ($3 > bpf) bpf = $3; if ($5 > bef) bef = $5
    if (!mrc || $2 < mrc) mrc = $2; if (!mpc || $4 < mpc) mpc = $4 }
  END {
    # median of the per-round ratios (insertion sort; n is small)
    for (i = 1; i <= n; i++) s[i] = ratio[i]
    for (i = 2; i <= n; i++) { v = s[i]; for (j = i - 1; j >= 1 && s[j] > v; j--) s[j + 1] = s[j]; s[j + 1] = v }
    med = (n % 2) ? s[(n + 1) / 2] : (s[n / 2] + s[n / 2 + 1]) / 2
    printf "best of %d: rayfarm render %.2f fps, povray %.2f fps (whole processes), rayfarm engine alone %.2f fps\n", n, brf, bpf, bef
    printf "ratio:   rayfarm render / povray = %.1fx in frames per second, best runs (median of rounds %.1fx; target >= 10x)\n", brf / bpf, med
    printf "engine:  rayfarm engine alone / povray = %.1fx\n", bef / bpf
    printf "cpu:     rayfarm render %.1f ms, povray %.1f ms of CPU per frame (least of each): %.1fx less work\n", mrc, mpc, mpc / mrc
  }'
echo "load afterwards $(cut -d' ' -f1-3 /proc/loadavg)"
