#!/usr/bin/env bash
# Benchmark (not a test): what posing a skinned mesh per frame costs a film. A skinned turntable
# (a generated 120×480-vertex strip on two joints, the upper joint swinging ±90° over a 2 s clip:
# 114k triangles) against the same file with its skin switched off (no "skin", no JOINTS/WEIGHTS:
# the joints still animate but move nothing), both 120 frames at 640x360, default quality, 2
# ranks, whole processes in turns. Prints the sustained fps of each, their ratio (target >= 0.8)
# and the per-frame pose + skin + BVH refit cost (anim_bench --model).
#   [REPEAT=3] bash bench/bench_skinned.sh [BUILD_DIR]       (default: build)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
bin=$build/bin/rayfarm
[ -x "$bin" ] || { echo "build $bin first (cmake --build $build --target rayfarm anim_bench)" >&2; exit 1; }
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
repeat=${REPEAT:-3}

python3 - "$tmp" <<'PY'
import base64, json, math, struct, sys
out = sys.argv[1]
NX, NY = 120, 480                          # vertices across and up: 1 wide, 2 tall
pos, jw, ww = bytearray(), bytearray(), bytearray()
for j in range(NY):
    for i in range(NX):
        x, y = i / (NX - 1), 2.0 * j / (NY - 1)
        pos += struct.pack('<3f', x - 0.5, y, 0.05 * math.sin(9 * x))
        w1 = min(1.0, max(0.0, y - 0.5))  # blend over the middle
        jw += struct.pack('<4B', 0, 1, 0, 0)
        ww += struct.pack('<4f', 1 - w1, w1, 0, 0)
idx = bytearray()
for j in range(NY - 1):
    for i in range(NX - 1):
        a = j * NX + i
        idx += struct.pack('<6I', a, a + 1, a + NX + 1, a, a + NX + 1, a + NX)
ibm = struct.pack('<16f', *[1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,0,1]) + struct.pack('<16f', *[1,0,0,0, 0,1,0,0, 0,0,1,0, 0,-1,0,1])
times = struct.pack('<5f', 0, 0.5, 1, 1.5, 2)
s = math.sqrt(0.5)
rots = struct.pack('<20f', 0,0,0,1, 0,0,s,s, 0,0,0,1, 0,0,-s,s, 0,0,0,1)
def build(skinned):
    blobs = [bytes(pos), bytes(idx), bytes(jw), bytes(ww), ibm, times, rots]
    views, accs, buf = [], [], bytearray()
    for b in blobs:
        views.append({"buffer": 0, "byteOffset": len(buf), "byteLength": len(b)}); buf += b
        while len(buf) % 4: buf += b'\0'
    nv = NX * NY
    accs = [{"bufferView": 0, "componentType": 5126, "count": nv, "type": "VEC3", "min": [-0.5, 0, -0.05], "max": [0.5, 2, 0.05]},
            {"bufferView": 1, "componentType": 5125, "count": len(idx) // 4, "type": "SCALAR"},
            {"bufferView": 2, "componentType": 5121, "count": nv, "type": "VEC4"},
            {"bufferView": 3, "componentType": 5126, "count": nv, "type": "VEC4"},
            {"bufferView": 4, "componentType": 5126, "count": 2, "type": "MAT4"},
            {"bufferView": 5, "componentType": 5126, "count": 5, "type": "SCALAR", "min": [0], "max": [2]},
            {"bufferView": 6, "componentType": 5126, "count": 5, "type": "VEC4"}]
    attrs = {"POSITION": 0}
    node = {"mesh": 0}
    if skinned:
        attrs.update({"JOINTS_0": 2, "WEIGHTS_0": 3}); node["skin"] = 0
    g = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0, 1]}],
         "nodes": [node, {"children": [2]}, {"translation": [0, 1, 0]}],
         "meshes": [{"primitives": [{"attributes": attrs, "indices": 1}]}],
         "skins": [{"joints": [1, 2], "inverseBindMatrices": 4}],
         "animations": [{"name": "swing", "channels": [{"sampler": 0, "target": {"node": 2, "path": "rotation"}}],
                         "samplers": [{"input": 5, "output": 6, "interpolation": "LINEAR"}]}],
         "accessors": accs, "bufferViews": views,
         "buffers": [{"byteLength": len(buf), "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(buf)).decode()}]}
    if not skinned: del g["skins"]
    json.dump(g, open(f"{out}/{'skinned' if skinned else 'frozen'}.gltf", "w"))
build(True); build(False)
PY

# Both without bounce light (--bounce 0): a film whose geometry moves has none by default, so the
# frozen film would otherwise light a cache every frame that the skinned one never builds.
run() {  # name file
  mpirun --oversubscribe -np 2 "$bin" render "$tmp/$2.gltf" -o "$tmp/$1.mp4" --no-frames --size 640x360 --frames 0:119 \
    --bounce 0 --stats "$tmp/$1.json" 2> "$tmp/$1.log" || { cat "$tmp/$1.log" >&2; exit 1; }
  python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['sustained_fps'])" "$tmp/$1.json"
}
echo "bench_skinned: $(nproc) CPUs, load $(cut -d' ' -f1-3 /proc/loadavg), $repeat runs each, in turns"
best_s=0 best_f=0
for r in $(seq "$repeat"); do
  f=$(run frozen frozen); s=$(run skinned skinned)
  echo "  run $r: frozen $f fps, skinned $s fps"
  best_f=$(python3 -c "print(max($best_f, $f))"); best_s=$(python3 -c "print(max($best_s, $s))")
done
python3 -c "import sys; f, s = $best_f, $best_s; print(f'best of {sys.argv[1]}: frozen {f:.2f} fps, skinned {s:.2f} fps, ratio {s / f:.3f} (target >= 0.8)')" "$repeat"
if [ -x "$build/bin/anim_bench" ]; then
  echo "per-frame timeline cost (Timeline::applyFrame: pose, skin, refit), one core:"
  "$build/bin/anim_bench" --model "$tmp/frozen.gltf" "$tmp/skinned.gltf"
fi
