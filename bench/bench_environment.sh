#!/usr/bin/env bash
# Benchmark (not a test): environment filtering time by shape (issue 30 #4). Two tables:
# 1. bench/env_bench: an EnvironmentLight made from texels of 8192 x 4096 pixels in six
#    shapes (2:1, 1:1, 8:1, 1:8, and the issue's strips 8 x 4,194,304 and 4,194,304 x 8, which a
#    file header is now refused for, but the filtering itself must not be slow on).
# 2. whole `rayfarm still env.json --size 32x18` processes with an .hdr of 8192 x 4096 pixels
#    (run-length encoded, 2 MB) at 2:1, 1:1 (5792 x 5792), 8:1 and 1:8, and the 8 x 4,194,304
#    strip (refused from its header in one line).
# With OLD_BUILD (a build of an earlier commit), each row runs the old binary then the new, in
# turns, and prints the ratio.
#   bash bench/bench_environment.sh [BUILD_DIR [OLD_BUILD_DIR]]     (default: build)
# Run it under `flock /work/bench.lock` on a shared machine, and note `uptime` beside it.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
old=${2:-}
export RAYFARM_BIN=${RAYFARM_BIN:-$build/bin/rayfarm}
source examples/common.sh

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
echo "load: $(uptime)"

echo "== env_bench (engine only, 2 threads)"
for b in ${old:+"$old"} "$build"; do
  [ -x "$b/bin/env_bench" ] || { echo "no $b/bin/env_bench (build target env_bench)"; continue; }
  echo "-- $b"
  "$b/bin/env_bench" --threads 2
done

for shape in "2to1 8192 4096" "1to1 5792 5792" "8to1 16384 2048" "1to8 2048 16384" "strip 8 4194304"; do
  set -- $shape
  python3 tests/farm/data/big_inputs.py hdr "$2" "$3" "$tmp/$1.hdr" "$tmp/$1.json"
done

echo "== rayfarm still SHAPE.json --size 32x18 (wall s; the old binary first when given)"
printf '%-22s %10s %10s %8s  %s\n' shape old new ratio "new's last line"
for name in 2to1 1to1 8to1 1to8 strip; do
  times=()
  for b in ${old:+"$old"} "$build"; do
    t0=$(date +%s.%N)
    (cd "$tmp" && "$OLDPWD/$b/bin/rayfarm" still "$name.json" --size 32x18 -o x.png > /dev/null 2> "$tmp/err") || true
    times+=("$(echo "$(date +%s.%N) - $t0" | bc -l)")
  done
  if [ -n "$old" ]; then
    printf '%-22s %10.2f %10.2f %8.2f  %s\n' "$name" "${times[0]}" "${times[1]}" "$(echo "${times[0]} / ${times[1]}" | bc -l)" "$(tail -1 "$tmp/err")"
  else
    printf '%-22s %10s %10.2f %8s  %s\n' "$name" - "${times[0]}" - "$(tail -1 "$tmp/err")"
  fi
done
