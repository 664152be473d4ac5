#!/usr/bin/env bash
# Builds the libFuzzer harnesses (clang, ASan + UBSan) and runs each for SECONDS (default 20).
#   bash tests/fuzz/run.sh [SECONDS]
# First replays every input in tests/fuzz/regressions/HARNESS/ (inputs that once crashed);
# then fuzzes from seed corpora made of scenes/ and assimp-testmodels. Exits non-zero on any
# crash, leak, timeout or sanitizer report; the input that did it is left in
# build-fuzz/findings/ (copy it into tests/fuzz/regressions/HARNESS/ once fixed).
# Prints one line per harness: executions, coverage (libFuzzer "cov" and "ft"), corpus size.
set -euo pipefail
secs=${1:-20}
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
build=${RAYFARM_FUZZ_BUILD:-$root/build-fuzz}
harnesses=(scene_json gltf_text glb scene_bundle farm_messages)
models=/usr/share/assimp/models/glTF2

cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ -DRAYFARM_FUZZ=ON \
  -DRAYFARM_BUILD_FARM=OFF -DRAYFARM_BUILD_TESTS=OFF -DRAYFARM_BUILD_BENCH=OFF -DRAYFARM_LTO=OFF >/dev/null
cmake --build "$build" -j"$(nproc 2>/dev/null || echo 2)" --target "${harnesses[@]/#/fuzz_}" >/dev/null

# Seed corpora (small files only: libFuzzer's input length is capped below).
seed() {  # seed HARNESS FILE...
  local dir="$build/corpus/$1"; shift
  mkdir -p "$dir"
  local f
  for f in "$@"; do
    [ -f "$f" ] && [ "$(stat -c %s "$f")" -le 65536 ] && cp -f "$f" "$dir/$(basename "$(dirname "$f")")-$(basename "$f")"
  done
  return 0
}
seed scene_json "$root"/scenes/*.json
# .gltf files that carry their buffers as data URIs load alone, as the harness reads them.
mapfile -t embedded < <(grep -rl --include='*.gltf' 'data:' "$models" 2>/dev/null || true)
seed gltf_text "$root"/scenes/*.gltf "${embedded[@]}"
mapfile -t glbs < <(find "$models" -name '*.glb' -size -64k 2>/dev/null)
seed glb "${glbs[@]}"
python3 - "$build/corpus" "$root/scenes" <<'PY'
import os, struct, sys
out, scenes = sys.argv[1], sys.argv[2]
def bundle(files):  # FileBundle::serialize: u64 count, then (u64 len, path, u64 len, bytes)
    b = struct.pack('<Q', len(files))
    for p, d in files:
        b += struct.pack('<Q', len(p)) + p.encode() + struct.pack('<Q', len(d)) + d
    return b
os.makedirs(f'{out}/scene_bundle', exist_ok=True)
for n in sorted(os.listdir(scenes)):
    if not os.path.isfile(os.path.join(scenes, n)):
        continue  # scenes/bench/ and other folders hold their own scenes
    with open(os.path.join(scenes, n), 'rb') as f:
        open(f'{out}/scene_bundle/{n}.bundle', 'wb').write(bundle([('scenes/' + n, f.read())]))
os.makedirs(f'{out}/farm_messages', exist_ok=True)
work = struct.pack('<5i', 3, 0, 0, 64, 64)
header = struct.pack('<6id5Q', 3, 0, 0, 2, 1, 0, 0.5, 2, 1, 0, 0, 0)
open(f'{out}/farm_messages/work', 'wb').write(b'\0' + work)
open(f'{out}/farm_messages/result', 'wb').write(b'\1' + header + bytes(6))
open(f'{out}/farm_messages/heartbeat', 'wb').write(b'\2' + bytes(16))
PY

mkdir -p "$build/findings"
status=0
for h in "${harnesses[@]}"; do
  bin="$build/bin/fuzz_$h"
  reg="$here/regressions/$h"
  if [ -d "$reg" ] && [ -n "$(ls -A "$reg")" ]; then
    if ! "$bin" -runs=0 "$reg"/* >"$build/findings/$h-replay.log" 2>&1; then
      echo "fuzz $h: a regression input fails again (see $build/findings/$h-replay.log)"
      status=1
    fi
  fi
  log="$build/findings/$h.log"
  if "$bin" -max_total_time="$secs" -timeout=25 -rss_limit_mb=2560 -max_len=65536 -print_final_stats=1 \
      -artifact_prefix="$build/findings/$h-" "$build/corpus/$h" >"$log" 2>&1; then
    result=ok
  else
    result="FAILED (see $log)"
    status=1
  fi
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo '?')
  last=$(grep -E '^#[0-9]+' "$log" | tail -1)
  cov=$(grep -o 'cov: [0-9]*' <<<"$last" || true)
  ft=$(grep -o 'ft: [0-9]*' <<<"$last" || true)
  corp=$(grep -o 'corp: [0-9/]*[a-zA-Z]*' <<<"$last" || true)
  echo "fuzz $h: ${secs}s, $execs executions, $cov $ft, $corp: $result"
done
exit $status
