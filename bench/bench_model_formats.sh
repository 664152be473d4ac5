#!/usr/bin/env bash
# Benchmark (not a test): loading one 10⁶-triangle mesh (a bumpy 708×708 grid, Y up) as binary
# STL and OBJ through assimp against the same triangles as GLB (issue 48; target: binary STL
# within 2× of the GLB). Two figures per file, best of REPEAT (default 3):
#   - whole processes: `rayfarm info FILE` (the whole load, BVH included, and the description)
#     and `rayfarm still FILE --size 32x18` (the load and a tiny render), wall seconds;
#   - the loader alone (model_load_bench): the file to the glTF model, and loadScene.
#   bash bench/bench_model_formats.sh [BUILD_DIR]       (default: build)
set -euo pipefail
cd "$(dirname "$0")/.."
build=${1:-build}
repeat=${REPEAT:-3}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

python3 - "$tmp" <<'PY'
import array, json, math, struct, sys
out = sys.argv[1]

n = 709
pos = array.array("f")
for j in range(n):
    for i in range(n):
        x, z = i / (n - 1) - 0.5, j / (n - 1) - 0.5
        pos.extend((x, 0.05 * math.sin(25 * x) * math.cos(25 * z), z))
idx = array.array("I")
for j in range(n - 1):
    for i in range(n - 1):
        a = j * n + i
        idx.extend((a, a + n, a + 1, a + 1, a + n, a + n + 1))
tris = len(idx) // 3
# GLB: indexed positions, as an exporter writes a shared-vertex mesh.
pb, ib = pos.tobytes(), idx.tobytes()
xs, ys, zs = pos[0::3], pos[1::3], pos[2::3]
gl = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
      "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
      "buffers": [{"byteLength": len(pb) + len(ib)}],
      "bufferViews": [{"buffer": 0, "byteLength": len(pb), "target": 34962},
                      {"buffer": 0, "byteOffset": len(pb), "byteLength": len(ib), "target": 34963}],
      "accessors": [{"bufferView": 0, "componentType": 5126, "count": len(pos) // 3, "type": "VEC3",
                     "min": [min(xs), min(ys), min(zs)], "max": [max(xs), max(ys), max(zs)]},
                    {"bufferView": 1, "componentType": 5125, "count": len(idx), "type": "SCALAR"}]}
js = json.dumps(gl).encode()
js += b" " * (-len(js) % 4)
binc = pb + ib
with open(f"{out}/mesh.glb", "wb") as f:
    f.write(struct.pack("<III", 0x46546C67, 2, 12 + 8 + len(js) + 8 + len(binc)))
    f.write(struct.pack("<II", len(js), 0x4E4F534A) + js)
    f.write(struct.pack("<II", len(binc), 0x004E4942) + binc)
# OBJ: the same vertices and faces (1-based), Y up.
with open(f"{out}/mesh.obj", "w") as f:
    f.write("".join("v %.6f %.6f %.6f\n" % (pos[3 * k], pos[3 * k + 1], pos[3 * k + 2]) for k in range(len(pos) // 3)))
    f.write("".join("f %d %d %d\n" % (idx[3 * t] + 1, idx[3 * t + 1] + 1, idx[3 * t + 2] + 1) for t in range(tris)))
# Binary STL: Z up by convention, so (x, y, z) is written as (x, -z, y); normals left 0.
rec = bytearray()
for t in range(tris):
    v = []
    for k in idx[3 * t:3 * t + 3]:
        v += (pos[3 * k], -pos[3 * k + 2], pos[3 * k + 1])
    rec += struct.pack("<12fH", 0, 0, 0, *v, 0)
with open(f"{out}/mesh.stl", "wb") as f:
    f.write(b"rayfarm bench".ljust(80, b" ") + struct.pack("<I", tris) + rec)
print(f"{tris} triangles, {len(pos) // 3} vertices", file=sys.stderr)
PY

best() {  # best wall seconds of $repeat runs of the command
    local b=""
    for _ in $(seq "$repeat"); do
        local t0 t1
        t0=$(date +%s.%N)
        "$@" > /dev/null 2> "$tmp/err" || { cat "$tmp/err" >&2; return 1; }
        t1=$(date +%s.%N)
        b=$(python3 -c "import sys; a=float(sys.argv[1]); b=sys.argv[2]; print(f'{a:.3f}' if not b or a < float(b) else b)" "$(echo "$t1 - $t0" | bc)" "$b")
    done
    echo "$b"
}

printf '%-10s %8s %14s %14s\n' file MB "info s" "still s"
for f in glb stl obj; do
    mb=$(python3 -c "import os,sys; print(f'{os.path.getsize(sys.argv[1])/1e6:.1f}')" "$tmp/mesh.$f")
    printf '%-10s %8s %14s %14s\n' "mesh.$f" "$mb" "$(best "$build/bin/rayfarm" info "$tmp/mesh.$f")" \
        "$(best "$build/bin/rayfarm" still "$tmp/mesh.$f" --size 32x18 -o "$tmp/x.png")"
done
echo "the loader alone (one process, best of $repeat):"
"$build/bin/model_load_bench" --repeat "$repeat" "$tmp/mesh.glb" "$tmp/mesh.stl" "$tmp/mesh.obj"
