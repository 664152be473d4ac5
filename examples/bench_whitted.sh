#!/usr/bin/env bash
# Benchmark (not a test): the Whitted orbit, 31 frames at 640×360, depth 5, 1 spp on all local
# cores, rendered by rayfarm and by POV-Ray 3.7 on shared/reference/whitted.pov with the command
# of shared/design.md. Prints both frame rates and their ratio.
#   bash examples/bench_whitted.sh [BUILD_DIR]       (default: build)
# Environment: POV_FILE (default ../shared/reference/whitted.pov), THREADS (default: nproc).
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
threads=${THREADS:-$(nproc 2>/dev/null || echo 2)}
pov=${POV_FILE:-../shared/reference/whitted.pov}

# POV-Ray is only needed here, so it is installed here (not by the test set-up).
if ! command -v povray >/dev/null; then bash tests/install-deps.sh povray; fi
bash tests/install-deps.sh
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DRAYFARM_BUILD_BENCH=ON >/dev/null
cmake --build "$build" -j"$threads" --target whitted_bench >/dev/null

out=$("$build/bin/whitted_bench" scenes/whitted.json --size 640x360 --frames 31 --depth 5 --threads "$threads")
echo "$out"
rf_fps=$(sed -n 's/.* \([0-9.]*\) fps.*/\1/p' <<<"$out")

[ -f "$pov" ] || { echo "bench_whitted: $pov not found (set POV_FILE)" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cp "$pov" "$tmp/whitted.pov"
start=$(date +%s.%N)
TIMEFORMAT="%U %S"
pov_cpu=$( { time (cd "$tmp" && povray +Iwhitted.pov +W640 +H360 -A +WT"$threads" +KFI0 +KFF30 +KI0 +KF1 -D >/dev/null 2>&1); } 2>&1 | awk '{ print $1 + $2 }')
end=$(date +%s.%N)
frames=$(ls "$tmp"/whitted*.png | wc -l)
pov_fps=$(awk -v n="$frames" -v a="$start" -v b="$end" 'BEGIN { printf "%.2f", n / (b - a) }')
echo "povray:  $frames frames 640x360, +WT$threads, no anti-aliasing: $(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.3f", b - a }') s, $pov_fps fps"
awk -v r="$rf_fps" -v p="$pov_fps" 'BEGIN { printf "ratio:   rayfarm / povray = %.1fx in frames per second (target >= 10x)\n", r / p }'
# On a shared machine wall time also counts other people's work; CPU time per frame does not.
rf_cpu=$(sed -n 's/.*CPU \([0-9.]*\) s.*/\1/p' <<<"$out")
awk -v r="$rf_cpu" -v p="$pov_cpu" -v n="$frames" 'BEGIN { printf "cpu:     rayfarm %.1f ms, povray %.1f ms of CPU per frame: %.1fx less work\n", 1e3 * r / 31, 1e3 * p / n, (p / n) / (r / 31) }'
