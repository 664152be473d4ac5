#!/usr/bin/env bash
# Benchmark (not a test): what chunked encoding costs against one encoder over the whole film,
# at equal CRF (issue 32). A real turntable (2CylinderEngine, --spp 1) is rendered once with its
# PNG frames kept; then the same frames are encoded again, whole `rayfarm render --resume`
# processes with every frame kept (nothing rendered), at several --chunk-frames K. K equal to the
# film's length is one encoder over the whole film: today's single encoder (then x264 makes one
# IDR picture either way; only its keyint setting differs, 250 before, infinite now). Printed
# per K: the file's size and the encoder's busy time from the --stats file (`encode_s`: the
# video thread, frames to packets), each against the single encoder.
#   [SIZES="640x360:120 1920x1080:120"] [KS="120 60 30 15"] bash bench/bench_chunks.sh [BUILD_DIR]
# Run it under `flock /work/bench.lock` on a shared host; it prints the load at start and end.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
bin=$(realpath "$build/bin/rayfarm")
model=/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb
# The default turntable has 120 frames; a size's frame count may not pass it.
sizes=${SIZES:-"640x360:120 1920x1080:120"}
ks=${KS:-"120 60 30 15"}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
tmp=$(mktemp -d)
trap '[ -n "${KEEP_TMP:-}" ] || rm -rf "$tmp"' EXIT
echo "bench_chunks: $(nproc) CPUs, load $(cut -d' ' -f1-3 /proc/loadavg)"
for sz in $sizes; do
  size=${sz%%:*} n=${sz##*:}
  dir=$tmp/frames_$size
  mpirun --oversubscribe -np 2 "$bin" render "$model" --size "$size" --spp 1 --frames "0:$((n - 1))" \
    --frames-dir "$dir" -o "$tmp/render_$size.mp4" 2> "$tmp/render_$size.log" || { cat "$tmp/render_$size.log"; exit 1; }
  for k in $ks; do
    [ "$k" -le "$n" ] || continue
    "$bin" render "$model" --size "$size" --spp 1 --frames "0:$((n - 1))" --frames-dir "$dir" --resume \
      --mode pixel --chunk-frames "$k" -o "$tmp/k${k}_$size.mp4" --stats "$tmp/k${k}_$size.json" 2> "$tmp/k${k}_$size.log" ||
      { cat "$tmp/k${k}_$size.log"; exit 1; }
    grep -q "$n of $n frames kept" "$tmp/k${k}_$size.log" || { cat "$tmp/k${k}_$size.log"; echo "frames were rendered again"; exit 1; }
  done
done
python3 - "$tmp" "$sizes" "$ks" <<'PY'
import json, os, sys
d, sizes, ks = sys.argv[1], sys.argv[2].split(), [int(k) for k in sys.argv[3].split()]
print(f"{'size':>10}{'frames':>7}{'K':>6}{'chunks':>7}{'bytes':>11}{'vs one':>8}{'encode s':>10}{'ms/frame':>10}{'vs one':>8}")
for sz in sizes:
    size, n = sz.split(":"); n = int(n)
    base = None
    for k in sorted((k for k in ks if k <= n), reverse=True):
        b = os.path.getsize(os.path.join(d, f"k{k}_{size}.mp4"))
        e = json.load(open(os.path.join(d, f"k{k}_{size}.json")))["encode_s"]
        if base is None: base = (b, e)
        print(f"{size:>10}{n:7}{k:6}{-(-n // k):7}{b:11}{b / base[0]:8.3f}{e:10.2f}{1000 * e / n:10.2f}{e / base[1]:8.3f}")
PY
echo "bench_chunks: load afterwards $(cut -d' ' -f1-3 /proc/loadavg)"
