#!/usr/bin/env bash
# Issue 42 #2, end to end: scenes/animated_pointers.gltf keys a spot light (intensity, colour,
# cone), the camera's yfov, a material (base colour, emissive strength) and a node's visibility
# through KHR_animation_pointer.
# 1. info lists each pointer the animation keys, and notes none as left out.
# 2. render --camera 0 through the farm: the kept frames are byte-identical in frame and pixel mode
#    at 1, 2 and 3 ranks and after --resume; they change over the film (first and last differ,
#    and so do two frames on either side of the marker's hiding at 1 s).
#   animation_pointer_farm_test.sh RAYFARM SOURCE_DIR WORK_DIR
set -euo pipefail
RAYFARM=$1 SRC=$2 WORK=$3
. "$SRC/tests/lib/refusal.sh"
. "$SRC/tests/lib/farm_modes.sh"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1 HWLOC_COMPONENTS=-gl
STAGE=$SRC/scenes/animated_pointers.gltf
rm -rf "$WORK"
mkdir -p "$WORK"
cd "$WORK"

# 1. info
"$RAYFARM" info --json "$STAGE" > stage.json 2>stage.err || { cat stage.err; fail "info --json"; }
python3 - stage.json <<'PY' || fail "info content"
import json, sys
d = json.load(open(sys.argv[1]))
paths = set(d["animations"][0]["paths"])
want = {"/extensions/KHR_lights_punctual/lights/0/intensity", "/cameras/0/perspective/yfov",
        "/materials/1/pbrMetallicRoughness/baseColorFactor", "/nodes/4/extensions/KHR_node_visibility/visible"}
assert want <= paths, paths
assert not any("KHR_animation_pointer" in n for n in d.get("notes", [])), d.get("notes")
v = d["camera_views"][0]
assert not v["animated"] and [a["name"] for a in v["lens_animations"]] == ["Show"], v
ext = {e["name"]: e for e in d["extensions"]}
assert ext["KHR_animation_pointer"]["supported"] and ext["KHR_node_visibility"]["supported"], ext
print("info ok")
PY

# 2. The farm: frame and pixel mode at 1 to 3 ranks, the same bytes.
common=(--camera 0 --size 48x28 --spp 1 --fps 4)  # 2 s at 4 fps: 8 frames
farm_modes_identical "$RAYFARM" "$STAGE" "${common[@]}"
grep -q "KHR_animation_pointer" np1_frame.log && fail "a pointer was left out: $(grep KHR_animation_pointer np1_frame.log)"
n=$(ls np1_frame/frame_*.png | wc -l)
[ "$n" -eq 8 ] || fail "expected 8 kept frames, got $n"
cmp -s np1_frame/frame_000000.png np1_frame/frame_000007.png && fail "nothing changed: frames 0 and 7 are the same"
cmp -s np1_frame/frame_000003.png np1_frame/frame_000004.png && fail "frames 3 and 4 (the marker hides at 1 s) are the same"
rm np3_pixel/frame_000002.png np3_pixel/frame_000005.png
mpirun --oversubscribe -np 3 "$RAYFARM" render "$STAGE" "${common[@]}" --mode pixel -o np3_pixel.mp4 --frames-dir np3_pixel \
    --resume 2>resume.log || { cat resume.log; fail "resume"; }
grep -q "resume: 6 of 8 frames kept" resume.log || { cat resume.log; fail "the resume did not render the 2 missing frames"; }
for f in np1_frame/frame_*.png; do
    cmp -s "$f" "np3_pixel/$(basename "$f")" || fail "$(basename "$f") differs after --resume"
done
echo "farm ok: $n frames identical at 1-3 ranks, frame and pixel mode, and after --resume"
