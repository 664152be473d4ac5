#!/usr/bin/env bash
# Benchmark (not a test): the inputs of the scaling model in docs/performance.md that one process
# gives. For the 2CylinderEngine turntable at the default quality, at 1920x1080 and 3840x2160, on
# ONE render thread (--threads 1): the CPU seconds a frame (user + system of the whole process,
# the run of N frames minus the run of 1, so loading and start-up cancel out), and from the
# longer run the bytes of a PNG frame, the video's bytes a frame and the encoder's busy time a
# frame (--stats encode_s; with films this short the chunks are 2 frames, so the encoder's
# start-up inflates it).
#   bash bench/bench_render_cost.sh [BUILD_DIR]   (default: build; about a minute)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
bin=$build/bin/rayfarm
if [ ! -x "$bin" ]; then
  bash tests/install-deps.sh
  cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$build" -j"$(nproc 2>/dev/null || echo 2)" --target rayfarm
fi
bin=$(realpath "$bin")
engine=/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp"
echo "bench_render_cost: $(nproc) CPUs, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'), load $(cut -d' ' -f1-3 /proc/loadavg)"
for spec in "1920x1080 3" "3840x2160 1"; do
  read -r size last <<< "$spec"
  for frames in 0:0 "0:$last"; do
    name=${size}_${frames/:/-}
    /usr/bin/time -f "%U %S" -o "$name.cpu" "$bin" render "$engine" --size "$size" --threads 1 --frames "$frames" \
      -o "$name.mp4" --stats "$name.json" 2> "$name.log" || { cat "$name.log" >&2; exit 1; }
  done
  python3 - "$size" "$last" <<'PY'
import glob, json, os, sys
size, last = sys.argv[1], int(sys.argv[2])
def cpu(name): return sum(float(x) for x in open(name + ".cpu").read().split())
one, many = f"{size}_0-0", f"{size}_0-{last}"
n = last + 1
per = (cpu(many) - cpu(one)) / (n - 1)
stats = json.load(open(many + ".json"))
pngs = glob.glob(many + ".frames/*.png")
png = sum(os.path.getsize(p) for p in pngs) / len(pngs)
video = os.path.getsize(many + ".mp4") / n
print(f"{size}: {per:.2f} CPU-s a frame on one core; PNG {png / 1e6:.2f} MB a frame; video {video / 1e3:.1f} kB a frame; "
      f"encoder {1000 * stats['encode_s'] / n:.1f} ms a frame")
PY
done
echo "bench_render_cost: load afterwards $(cut -d' ' -f1-3 /proc/loadavg)"
