#!/usr/bin/env bash
# Benchmark (not a test): the Whitted orbit, 31 frames at 640×360, depth 5, 1 spp on all local
# cores, rendered by rayfarm and by POV-Ray 3.7 on shared/reference/whitted.pov with the command
# of shared/design.md. Prints both frame rates and their ratio.
#   bash examples/bench_whitted.sh [BUILD_DIR]       (default: build)
# Environment: POV_FILE (default ../shared/reference/whitted.pov), THREADS (default: nproc),
# REPEAT (default 3): the two renderers take turns this many times. On a shared machine a run can
# lose a third of its speed to other work, so the summary compares each one's best run (the least
# disturbed) and also gives the median of the per-round ratios.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
threads=${THREADS:-$(nproc 2>/dev/null || echo 2)}
pov=${POV_FILE:-../shared/reference/whitted.pov}
repeat=${REPEAT:-3}

# POV-Ray is only needed here, so it is installed here (not by the test set-up).
if ! command -v povray >/dev/null; then bash tests/install-deps.sh povray; fi
bash tests/install-deps.sh
cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release -DRAYFARM_BUILD_BENCH=ON >/dev/null
cmake --build "$build" -j"$threads" --target whitted_bench >/dev/null
[ -f "$pov" ] || { echo "bench_whitted: $pov not found (set POV_FILE)" >&2; exit 1; }

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cp "$pov" "$tmp/whitted.pov"
TIMEFORMAT="%U %S"
rounds=()   # "rf_fps rf_cpu_ms pov_fps pov_cpu_ms" per round
for ((i = 1; i <= repeat; i++)); do
  out=$("$build/bin/whitted_bench" scenes/whitted.json --size 640x360 --frames 31 --depth 5 --threads "$threads")
  echo "round $i $out"
  rf_fps=$(sed -n 's/.* \([0-9.]*\) fps.*/\1/p' <<<"$out")
  rf_cpu=$(sed -n 's/.*, \([0-9.]*\) ms CPU per frame.*/\1/p' <<<"$out")

  rm -f "$tmp"/whitted*.png
  start=$(date +%s.%N)
  pov_cpu=$( { time (cd "$tmp" && povray +Iwhitted.pov +W640 +H360 -A +WT"$threads" +KFI0 +KFF30 +KI0 +KF1 -D >/dev/null 2>&1); } 2>&1 | awk '{ print $1 + $2 }')
  end=$(date +%s.%N)
  frames=$(ls "$tmp"/whitted*.png | wc -l)
  pov_fps=$(awk -v n="$frames" -v a="$start" -v b="$end" 'BEGIN { printf "%.2f", n / (b - a) }')
  pov_ms=$(awk -v p="$pov_cpu" -v n="$frames" 'BEGIN { printf "%.1f", 1e3 * p / n }')
  echo "round $i povray:  $frames frames 640x360, +WT$threads, no anti-aliasing: $(awk -v a="$start" -v b="$end" 'BEGIN { printf "%.3f", b - a }') s, $pov_fps fps, $pov_ms ms CPU per frame"
  rounds+=("$rf_fps $rf_cpu $pov_fps $pov_ms")
done

printf '%s\n' "${rounds[@]}" | awk -v n="$repeat" '
  { rf[NR] = $1; rc[NR] = $2; pf[NR] = $3; pc[NR] = $4; ratio[NR] = $1 / $3
    if ($1 > brf) brf = $1; if ($3 > bpf) bpf = $3
    if (!mrc || $2 < mrc) mrc = $2; if (!mpc || $4 < mpc) mpc = $4 }
  END {
    # median of the per-round ratios (insertion sort; n is small)
    for (i = 1; i <= n; i++) s[i] = ratio[i]
    for (i = 2; i <= n; i++) { v = s[i]; for (j = i - 1; j >= 1 && s[j] > v; j--) s[j + 1] = s[j]; s[j + 1] = v }
    med = (n % 2) ? s[(n + 1) / 2] : (s[n / 2] + s[n / 2 + 1]) / 2
    printf "best of %d: rayfarm %.2f fps, povray %.2f fps\n", n, brf, bpf
    printf "ratio:   rayfarm / povray = %.1fx in frames per second, best runs (median of rounds %.1fx; target >= 10x)\n", brf / bpf, med
    printf "cpu:     rayfarm %.1f ms, povray %.1f ms of CPU per frame (least of each): %.1fx less work\n", mrc, mpc, mpc / mrc
  }'
