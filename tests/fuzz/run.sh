#!/usr/bin/env bash
# Builds the libFuzzer harnesses (clang, ASan + UBSan) and runs each for SECONDS (default 20).
#   bash tests/fuzz/run.sh [SECONDS [HARNESS...]]   (default: every harness, one after another)
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
# Models through assimp: a harness per format (fuzz_obj, fuzz_stl, fuzz_ply, fuzz_fbx, fuzz_dae,
# fuzz_3mf), all six in the default run. Debian's assimp 5.2.5 itself fails on some inputs within
# seconds (a 3MF that makes it abort(), a PLY it spins on, a 42 KB COLLADA file on which it
# allocates gigabytes, an FBX it frees a buffer of twice: tests/fuzz/assimp_crashes/); since it
# reads in a child process with a time and a memory limit (engine/load/assimp/assimp_isolated.h),
# those are refused files, and a finding is a failure of rayfarm's own.
harnesses=(scene_json gltf_text glb scene_bundle farm_messages environment obj stl ply fbx dae 3mf)
[ $# -gt 1 ] && harnesses=("${@:2}")
models=/usr/share/assimp/models/glTF2

cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ -DRAYFARM_FUZZ=ON \
  -DRAYFARM_BUILD_FARM=OFF -DRAYFARM_BUILD_TESTS=OFF -DRAYFARM_BUILD_BENCH=OFF -DRAYFARM_LTO=OFF >/dev/null
cmake --build "$build" -j"$(nproc 2>/dev/null || echo 2)" --target "${harnesses[@]/#/fuzz_}" >/dev/null

# libFuzzer's input length cap: 64 KiB, and 128 KiB for environment images (the shipped studio
# .exr, a DWAB file, is 96 KiB).
max_len() { [ "$1" = environment ] && echo 131072 || echo 65536; }
# assimp leaks on its own error paths (a mesh, a zlib stream: inside libassimp.so, never in
# rayfarm's frames), so leak detection is off for the model harnesses; rayfarm's conversion
# holds everything in containers.
# libFuzzer's malloc limit hooks every allocation, the importer's child's too (which would then
# write an artifact of its own): raised for them, where the child's RLIMIT_DATA bounds assimp and
# -rss_limit_mb still bounds the harness.
extra_flags() { case "$1" in obj|stl|ply|fbx|dae|3mf) echo "-detect_leaks=0 -malloc_limit_mb=1048576" ;; esac; }
asan_options() { case "$1" in obj|stl|ply|fbx|dae|3mf) echo detect_leaks=0 ;; *) echo "${ASAN_OPTIONS:-}" ;; esac; }

# Seed corpora (small files only: libFuzzer's input length is capped below).
seed() {  # seed HARNESS FILE...
  local dir="$build/corpus/$1" limit
  limit=$(max_len "$1")
  shift
  mkdir -p "$dir"
  local f
  for f in "$@"; do
    [ -f "$f" ] && [ "$(stat -c %s "$f")" -le "$limit" ] && cp -f "$f" "$dir/$(basename "$(dirname "$f")")-$(basename "$f")"
  done
  return 0
}
seed scene_json "$root"/scenes/*.json
# .gltf files that carry their buffers as data URIs load alone, as the harness reads them.
mapfile -t embedded < <(grep -rl --include='*.gltf' 'data:' "$models" 2>/dev/null || true)
# Seeds written for checks the shipped files do not reach (lights, IOR: issue 46).
seed gltf_text "$root"/scenes/*.gltf "$root"/tests/fuzz/seeds/gltf_text/*.gltf "${embedded[@]}"
mapfile -t glbs < <(find "$models" -name '*.glb' -size -64k 2>/dev/null)
seed glb "${glbs[@]}"
seed environment "$root"/scenes/environments/*.exr
# Models through assimp: assimp-testmodels' own files of each format, and Blender's exports.
for fmt in obj stl ply fbx dae 3mf; do
  mapfile -t files < <(find /usr/share/assimp/models "$root/tests/reference/assimp" -iname "*.$fmt" -size -64k 2>/dev/null)
  seed "$fmt" "${files[@]}"
done
# Compressed geometry for the glb harness (its BIN chunk is what the decoders read, so mutations
# land in the Draco and meshopt streams): gltfpack's meshopt copies of small project models, and
# below, one primitive of Debian's Draco 2CylinderEngine cut into a GLB of its own.
if command -v gltfpack >/dev/null; then
  for m in "$root"/scenes/animated_node.gltf "$root"/tests/reference/textured_spot.gltf; do
    gltfpack -i "$m" -o "$build/corpus/glb/meshopt-$(basename "$m" .gltf).glb" -cc >/dev/null 2>&1 || true
  done
fi
python3 - "$build/corpus/glb" "$models/draco/2CylinderEngine.gltf" <<'PY'
import json, os, struct, sys
out, src = sys.argv[1], sys.argv[2]
if not os.path.exists(src):
    sys.exit(0)
g = json.load(open(src))
bin_ = open(os.path.join(os.path.dirname(src), g['buffers'][0]['uri']), 'rb').read()
for mesh in (0, 1):
    prim = g['meshes'][mesh]['primitives'][0]
    ext = prim['extensions']['KHR_draco_mesh_compression']
    view = g['bufferViews'][ext['bufferView']]
    data = bin_[view.get('byteOffset', 0):view.get('byteOffset', 0) + view['byteLength']]
    accs = {}
    for name, a in list(prim['attributes'].items()) + [('indices', prim['indices'])]:
        accs[a] = len(accs)
    accessors = [dict(g['accessors'][a]) for a in accs]
    for a in accessors:
        a.pop('bufferView', None)
    p = {'attributes': {n: accs[a] for n, a in prim['attributes'].items()}, 'indices': accs[prim['indices']],
         'extensions': {'KHR_draco_mesh_compression': {'bufferView': 0, 'attributes': ext['attributes']}}}
    doc = {'asset': {'version': '2.0'}, 'extensionsUsed': ['KHR_draco_mesh_compression'],
           'extensionsRequired': ['KHR_draco_mesh_compression'], 'scene': 0, 'scenes': [{'nodes': [0]}],
           'nodes': [{'mesh': 0}], 'meshes': [{'primitives': [p]}], 'accessors': accessors,
           'bufferViews': [{'buffer': 0, 'byteLength': len(data)}], 'buffers': [{'byteLength': len(data)}]}
    j = json.dumps(doc).encode()
    j += b' ' * (-len(j) % 4)
    data += b'\0' * (-len(data) % 4)
    glb = b'glTF' + struct.pack('<II', 2, 12 + 8 + len(j) + 8 + len(data)) + struct.pack('<II', len(j), 0x4E4F534A) + j
    glb += struct.pack('<II', len(data), 0x004E4942) + data
    open(os.path.join(out, 'draco-2CylinderEngine-mesh%d.glb' % mesh), 'wb').write(glb)
PY
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
# Small made-up environment images: Radiance .hdr flat and run-length coded, OpenEXR uncompressed.
env = f'{out}/environment'
os.makedirs(env, exist_ok=True)
def hdr(w, h, rle):
    head = b'#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y %d +X %d\n' % (h, w)
    rows = b''
    for y in range(h):
        px = [((x * 37 + y * 11) % 256, (x * 5) % 256, (y * 50) % 256, 128 + (x + y) % 8) for x in range(w)]
        if not rle:
            rows += b''.join(bytes(p) for p in px)
            continue
        rows += bytes([2, 2, w >> 8, w & 255])
        for c in range(4):  # each component: one literal run of the first half, one repeat run
            half = w // 2
            rows += bytes([half]) + bytes(p[c] for p in px[:half]) + bytes([128 + (w - half), px[half][c]])
    return head + rows
open(f'{env}/flat.hdr', 'wb').write(hdr(4, 2, False))
open(f'{env}/rle.hdr', 'wb').write(hdr(16, 4, True))
def exr(w, h):  # scanline, NO_COMPRESSION, half B, G, R
    def attr(name, kind, data):
        return name.encode() + b'\0' + kind.encode() + b'\0' + struct.pack('<i', len(data)) + data
    chl = b''.join(c.encode() + b'\0' + struct.pack('<i4Bii', 1, 0, 0, 0, 0, 1, 1) for c in 'BGR') + b'\0'
    box = struct.pack('<4i', 0, 0, w - 1, h - 1)
    head = (struct.pack('<ii', 20000630, 2) + attr('channels', 'chlist', chl) + attr('compression', 'compression', b'\0') +
            attr('dataWindow', 'box2i', box) + attr('displayWindow', 'box2i', box) + attr('lineOrder', 'lineOrder', b'\0') +
            attr('pixelAspectRatio', 'float', struct.pack('<f', 1)) + attr('screenWindowCenter', 'v2f', struct.pack('<ff', 0, 0)) +
            attr('screenWindowWidth', 'float', struct.pack('<f', 1)) + b'\0')
    half = lambda v: struct.unpack('<H', struct.pack('<e', v))[0]
    blocks, offsets = b'', []
    start = len(head) + 8 * h
    for y in range(h):
        line = b''.join(struct.pack('<%dH' % w, *[half(0.1 * (x + c + y)) for x in range(w)]) for c in range(3))
        offsets.append(start + len(blocks))
        blocks += struct.pack('<ii', y, len(line)) + line
    return head + struct.pack('<%dQ' % h, *offsets) + blocks
open(f'{env}/tiny.exr', 'wb').write(exr(8, 4))
PY

mkdir -p "$build/findings"
status=0
for h in "${harnesses[@]}"; do
  bin="$build/bin/fuzz_$h"
  reg="$here/regressions/$h"
  if [ -d "$reg" ] && [ -n "$(ls -A "$reg")" ]; then
    # shellcheck disable=SC2046
    if ! ASAN_OPTIONS=$(asan_options "$h") "$bin" -runs=0 $(extra_flags "$h") "$reg"/* >"$build/findings/$h-replay.log" 2>&1; then
      echo "fuzz $h: a regression input fails again (see $build/findings/$h-replay.log)"
      status=1
    fi
  fi
  log="$build/findings/$h.log"
  # shellcheck disable=SC2046
  if ASAN_OPTIONS=$(asan_options "$h") "$bin" -max_total_time="$secs" -timeout=25 -rss_limit_mb=2560 -max_len="$(max_len "$h")" -print_final_stats=1 $(extra_flags "$h") \
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
