#!/usr/bin/env bash
# Issue 48, end to end: models that are not glTF through the real binary.
# 1. An OBJ with an MTL and textures (assimp-testmodels' spider) as a turntable through the
#    farm: the kept frames and the video are byte-identical in frame and pixel mode at 1 and 3
#    ranks (the workers import the same OBJ, MTL and JPEGs from rank 0's bundle).
# 2. info describes an OBJ and an STL as the glTF model each became, its format named.
# 3. Refusals, one line and exit 2: a format assimp reads that rayfarm does not vouch for, a
#    malformed STL, an MTL texture outside the asset root.
#   assimp_models_test.sh RAYFARM SOURCE_DIR WORK_DIR
set -euo pipefail
RAYFARM=$1 SRC=$2 WORK=$3
. "$SRC/tests/lib/refusal.sh"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1 HWLOC_COMPONENTS=-gl
SPIDER=/usr/share/assimp/models/OBJ/spider.obj
[ -f "$SPIDER" ] || fail "$SPIDER missing (package assimp-testmodels)"
rm -rf "$WORK"
mkdir -p "$WORK"
cd "$WORK"

# 1. The farm.
common=(--size 48x28 --spp 1 --fps 3)
render_np() {  # np mode
    mpirun --oversubscribe -np "$1" "$RAYFARM" render "$SPIDER" "${common[@]}" --mode "$2" -o "np$1_$2.mp4" \
        --frames-dir "np$1_$2" 2>"np$1_$2.log" || { cat "np$1_$2.log"; fail "render np $1 $2"; }
}
render_np 1 frame
n=$(ls np1_frame/frame_*.png | wc -l)
[ "$n" -ge 6 ] || fail "expected a turntable of several frames, got $n"
cmp -s np1_frame/frame_000000.png "np1_frame/frame_$(printf %06d $((n / 2))).png" && fail "the turntable does not turn"
for run in "3 frame" "3 pixel"; do
    render_np $run
    d=np${run// /_}
    for f in np1_frame/frame_*.png; do
        cmp -s "$f" "$d/$(basename "$f")" || fail "$(basename "$f") differs between np 1 frame mode and $run"
    done
    cmp -s np1_frame.mp4 "$d.mp4" || fail "the video differs between np 1 frame mode and $run"
done
echo "farm ok: $n frames of spider.obj identical at 1 and 3 ranks, frame and pixel mode"

# 2. info
"$RAYFARM" info "$SPIDER" > spider.txt 2>/dev/null || fail "info spider.obj"
grep -q "^$SPIDER: OBJ read as glTF 2.0 from \"assimp 5" spider.txt || fail "info text: $(head -1 spider.txt)"
"$RAYFARM" info --json /usr/share/assimp/models/STL/Spider_binary.stl > stl.json 2>/dev/null || fail "info --json stl"
python3 - stl.json <<'PY' || fail "info --json content"
import json, sys
j = json.load(open(sys.argv[1]))
assert j["format"] == "STL", j.get("format")
assert j["triangles"] > 1000, j["triangles"]
assert j["turntable"]["frames"] > 1, j["turntable"]
print("info ok:", j["triangles"], "triangles")
PY

# 3. Refusals
printf 'not really a 3ds file' > ship.3ds
expect_refusal --exact "ship.3ds: rayfarm does not read .3ds files (assimp could, but rayfarm is not tested on them); it reads .json scene files, glTF (.gltf, .glb) and through assimp .obj, .stl, .ply, .fbx, .dae and .3mf" \
    "$RAYFARM" still ship.3ds -o x.png
head -c 300 /usr/share/assimp/models/STL/Spider_binary.stl > cut.stl
expect_refusal --prefix "cut.stl: " "$RAYFARM" still cut.stl -o x.png
expect_refusal --prefix "cut.stl: " "$RAYFARM" info cut.stl
mkdir -p inside
printf 'v 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\nmtllib m.mtl\nusemtl m\nf 1/1 2/1 3/1\n' > inside/t.obj
printf 'newmtl m\nKd 1 1 1\nmap_Kd ../secret.png\n' > inside/m.mtl
cp "$SRC/examples/contact-box-after.png" secret.png
expect_refusal "outside the asset root" "$RAYFARM" still inside/t.obj -o x.png --asset-root inside
# A file on which Debian's libassimp frees a buffer twice (found by fuzzing): assimp reads in a
# child process, so the crash costs the child and rayfarm refuses the file with one line. (Whether
# glibc notices the double free depends on the heap's state; where it does not, the child reads
# on and the file is refused for a texture outside its folder: one line either way.)
crash=$SRC/tests/fuzz/assimp_crashes/fbx-double-free.fbx
expect_refusal --prefix "$crash: " "$RAYFARM" still "$crash" -o x.png
expect_refusal --prefix "$crash: " "$RAYFARM" info "$crash"
echo "refusals ok"
