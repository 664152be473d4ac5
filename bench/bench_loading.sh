#!/usr/bin/env bash
# Benchmark (not a test): loading time of large generated inputs (issue 30), each as a whole
# `rayfarm still INPUT --size 32x18 -o x.png` process (start-up, JSON parse, the loaders'
# checks, BVH build, a 32x18 render). Prints a table: input, file size, wall seconds, peak RSS.
#   bash bench/bench_loading.sh [BUILD_DIR]       (default: build)
# Inputs (SCALE=k divides every count by k, for a quick look):
#   - a scene file with 100,000 materials (the duplicate-key check; was 30 s at 40,000)
#   - a scene file with 1,000,000 spheres, none touching (the overlap check; was 37 s at 100,000)
#   - a glTF whose 1,000,000 nodes form one chain (the cycle walk; was 15 s at 100,000)
#   - a glTF whose asset.extras holds 100,000 keys (the duplicate-key check; was 23 s at 40,000)
# Target: each in seconds.
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
scale=${SCALE:-1}
export RAYFARM_BIN=${RAYFARM_BIN:-$build/bin/rayfarm}
source examples/common.sh

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

python3 - "$tmp" "$scale" <<'PY'
import base64, json, struct, sys
out, scale = sys.argv[1], int(sys.argv[2])
base = {"camera": {"eye": [0, 40, -300], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 50},
        "lights": [{"type": "point", "position": [0, 500, -500], "color": [1, 1, 1]}],
        "render": {"width": 32, "height": 18}}

n = 100000 // scale
s = dict(base, materials={f"m{i}": {"color": [0.5, 0.5, 0.5]} for i in range(n)},
         objects=[{"type": "sphere", "center": [0, 0, 0], "radius": 50, "material": "m0"}])
json.dump(s, open(f"{out}/materials.json", "w"))

n = 1000000 // scale
side = round(n ** (1 / 3)) + 1
objs = []
for i in range(n):
    x, y, z = i % side, (i // side) % side, i // (side * side)
    objs.append({"type": "sphere", "center": [3 * x - 1.5 * side, 3 * y - 1.5 * side, 3 * z - 1.5 * side], "radius": 1,
                 "material": "m"})
s = dict(base, materials={"m": {"color": [0.8, 0.3, 0.2]}}, objects=objs)
json.dump(s, open(f"{out}/spheres.json", "w"))

# One triangle, as a data URI.
buf = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
uri = "data:application/octet-stream;base64," + base64.b64encode(buf).decode()
def gltf(nodes, extras=None):
    g = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": nodes,
         "meshes": [{"primitives": [{"attributes": {"POSITION": 0}}]}],
         "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 0]}],
         "bufferViews": [{"buffer": 0, "byteLength": len(buf)}], "buffers": [{"byteLength": len(buf), "uri": uri}]}
    if extras is not None: g["asset"]["extras"] = extras
    return g
n = 1000000 // scale
nodes = [{"children": [i + 1]} for i in range(n - 1)] + [{"mesh": 0}]
json.dump(gltf(nodes), open(f"{out}/chain.gltf", "w"))
n = 100000 // scale
json.dump(gltf([{"mesh": 0}], {f"key{i}": i for i in range(n)}), open(f"{out}/extras.gltf", "w"))
PY

printf '%-44s %10s %10s %12s\n' input "file MB" "wall s" "peak RSS MB"
row() {  # label file
    local t0 t1 rss
    t0=$(date +%s.%N)
    /usr/bin/time -f %M -o "$tmp/rss" "$bin" still "$2" --size 32x18 -o "$tmp/x.png" 2> "$tmp/err" ||
        { cat "$tmp/err" >&2; echo "bench_loading: $1 failed" >&2; exit 1; }
    t1=$(date +%s.%N)
    rss=$(tail -1 "$tmp/rss")
    printf '%-44s %10.1f %10.2f %12.0f\n' "$1" "$(echo "$(stat -c %s "$2") / 1048576" | bc -l)" "$(echo "$t1 - $t0" | bc -l)" \
        "$(echo "$rss / 1024" | bc -l)"
}
row "$((100000 / scale)) materials (scene file)" "$tmp/materials.json"
row "$((1000000 / scale)) spheres, none touching (scene file)" "$tmp/spheres.json"
row "$((1000000 / scale))-node chain (glTF)" "$tmp/chain.gltf"
row "$((100000 / scale)) keys in asset.extras (glTF)" "$tmp/extras.gltf"
