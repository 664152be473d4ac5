#!/usr/bin/env bash
# Issue 42, end to end on files no one here wrote by hand: Blender 3.4's own export
# (tests/reference/animated_camera.gltf, from make_animated_camera.py: a camera flown over 2 s,
# three cubes with an animation each, two scenes) and assimp's Cameras.gltf.
# 1. info marks each camera still or animated and by what, lists the scenes, plays every
#    animation and says how many whole plays each gets; info --camera 0 describes the film.
# 2. render --camera 0 through the farm: the kept frames are byte-identical in frame and pixel
#    mode at 1, 2 and 3 ranks, and after --resume (a resume through another scene refused); the camera moves (first and last frame differ); still --camera 0
#    at two frames differs too (it used to show the rest pose at every frame).
# 3. --scene 0 draws the other scene; a --camera or --scene the file lacks, from render, still,
#    info and a scene file's keys, is one line and exit 2 naming it.
#   file_camera_test.sh RAYFARM SOURCE_DIR WORK_DIR
set -euo pipefail
RAYFARM=$1 SRC=$2 WORK=$3
. "$SRC/tests/lib/refusal.sh"
. "$SRC/tests/lib/farm_modes.sh"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1 HWLOC_COMPONENTS=-gl
FLY=$SRC/tests/reference/animated_camera.gltf
CAMS=/usr/share/assimp/models/glTF2/cameras/Cameras.gltf
[ -f "$CAMS" ] || fail "$CAMS missing (package assimp-testmodels)"
rm -rf "$WORK"
mkdir -p "$WORK"
cd "$WORK"

# 1. info
"$RAYFARM" info --json "$FLY" > fly.json 2>/dev/null || fail "info --json"
"$RAYFARM" info "$FLY" > fly.txt 2>/dev/null || fail "info"
"$RAYFARM" info --json --camera 0 "$FLY" > fly_cam.json 2>/dev/null || fail "info --json --camera 0"
"$RAYFARM" info --json "$CAMS" > cams.json 2>/dev/null || fail "info Cameras.gltf"
python3 - fly.json fly_cam.json cams.json <<'PY' || fail "info content"
import json, sys
fly, cam, cams = (json.load(open(p)) for p in sys.argv[1:4])
v = fly["camera_views"]
assert len(v) == 1 and v[0]["animated"] and [a["name"] for a in v[0]["animations"]] == ["CameraFly"], v
assert v[0]["node_name"] == "FlyCam", v
sc = fly["scenes"]
assert [s["name"] for s in sc] == ["Spare", "Stage"] and sc[1]["default"] and sc[1]["drawn"] and not sc[0]["drawn"], sc
# Every animation plays (one per object, on different nodes); the 4 s turntable holds whole
# plays of the longest (2.042 s: 2 plays), the 1.042 s hop loops 3.92 times (3 whole).
anims = {a["name"]: a for a in fly["turntable"]["animations"]}
assert set(anims) == {"RedSpin", "GreenHop", "BlueSlide", "CameraFly"}, anims
assert fly["turntable"]["through"] == "turntable"
assert anims["RedSpin"]["ends_whole"] and anims["RedSpin"]["whole_plays"] == 2, anims["RedSpin"]
assert not anims["GreenHop"]["ends_whole"] and anims["GreenHop"]["whole_plays"] == 3, anims["GreenHop"]
t = cam["turntable"]
assert t["through"] == 0 and t["frames"] == 62, t
assert {a["name"]: a["whole_plays"] for a in t["animations"]}["CameraFly"] == 1, t["animations"]
cv = cams["camera_views"]
assert len(cv) == 2 and not any(c["animated"] for c in cv), cv
assert all(c["rendered"] for c in cams["cameras"]), cams["cameras"]
print("info ok")
PY
grep -q 'animated by 3 "CameraFly"' fly.txt || fail "info text does not say the camera is animated: $(grep -- '--camera' fly.txt)"
grep -q '"Spare": 3 root nodes$' fly.txt || fail "info text does not list scene 0"
grep -q '2 whole plays' fly.txt || fail "info text does not count whole plays"

# 2. The farm: frame and pixel mode at 1 to 3 ranks, the same bytes.
common=(--camera 0 --size 48x28 --spp 1 --fps 6 --exposure 0 --tonemap clamp)  # 13 frames: 49/24 s at 6 fps, both ends
farm_modes_identical "$RAYFARM" "$FLY" "${common[@]}"
n=$(ls np1_frame/frame_*.png | wc -l)
[ "$n" -eq 13 ] || fail "expected 13 kept frames, got $n"
cmp -s np1_frame/frame_000000.png np1_frame/frame_000012.png && fail "the camera did not move: frames 0 and 12 are the same"
"$RAYFARM" still "$FLY" --camera 0 --size 48x27 --spp 1 --frame 0 -o still0.png 2>/dev/null || fail "still --frame 0"
"$RAYFARM" still "$FLY" --camera 0 --size 48x27 --spp 1 --frame 40 -o still40.png 2>/dev/null || fail "still --frame 40"
cmp -s still0.png still40.png && fail "still --camera 0 shows the same picture at frames 0 and 40"
# --resume: frames deleted from the 3-rank pixel run are rendered again to the same bytes; a
# resume through another camera or scene is refused naming it.
rm np3_pixel/frame_000004.png np3_pixel/frame_000009.png
expect_refusal "gltf_scene was not given, now 0" \
    "$RAYFARM" render "$FLY" "${common[@]}" --scene 0 -o np3_pixel.mp4 --frames-dir np3_pixel --resume
mpirun --oversubscribe -np 3 "$RAYFARM" render "$FLY" "${common[@]}" --mode pixel -o np3_pixel.mp4 --frames-dir np3_pixel \
    --resume 2>resume.log || { cat resume.log; fail "resume"; }
grep -q "resume: 11 of 13 frames kept" resume.log || { cat resume.log; fail "the resume did not render the 2 missing frames"; }
for f in np1_frame/frame_*.png; do
    cmp -s "$f" "np3_pixel/$(basename "$f")" || fail "$(basename "$f") differs after --resume"
done
echo "farm ok: $n frames identical at 1-3 ranks, frame and pixel mode, and after --resume"

# 3. --scene, and bad input
"$RAYFARM" still "$FLY" --scene 0 --camera 0 --size 48x27 --spp 1 -o spare.png 2>/dev/null || fail "still --scene 0"
cmp -s spare.png still0.png && fail "--scene 0 shows scene 1"
expect_refusal --exact "$FLY: --camera: no camera 1 (the file has 1 camera)" "$RAYFARM" render "$FLY" --camera 1 -o bad.mp4 --size 48x27
expect_refusal --exact "$FLY: --scene: no scene 2 (the file has 2 scenes)" "$RAYFARM" render "$FLY" --scene 2 -o bad.mp4 --size 48x27
expect_refusal --exact "$FLY: --scene: no scene 5 (the file has 2 scenes)" "$RAYFARM" still "$FLY" --scene 5 -o bad.png
expect_refusal --exact "$FLY: --camera: no camera 3 (the file has 1 camera)" "$RAYFARM" info "$FLY" --camera 3
expect_refusal --exact "$CAMS: --camera: no camera 2 (the file has 2 cameras)" "$RAYFARM" still "$CAMS" --camera 2 -o bad.png
expect_refusal --exact "$CAMS: --camera: no camera 2 (the file has 2 cameras)" "$RAYFARM" render "$CAMS" --camera 2 -o bad.mp4
# Under mpirun: rayfarm's one line (mpirun adds its own words about the exit), status 2.
set +e
mpirun --oversubscribe -np 2 "$RAYFARM" render "$FLY" --camera 1 -o bad.mp4 --size 48x27 >/dev/null 2>mpi_bad.log
status=$?
set -e
[ "$status" -eq 2 ] || fail "mpirun -np 2 render --camera 1: exit status $status, expected 2"
[ "$(grep -c '^rayfarm:' mpi_bad.log)" -eq 1 ] || fail "mpirun -np 2 render --camera 1: expected one rayfarm line: $(cat mpi_bad.log)"
grep -qxF "rayfarm: error: $FLY: --camera: no camera 1 (the file has 1 camera)" mpi_bad.log ||
    fail "mpirun -np 2 render --camera 1: unexpected message: $(grep '^rayfarm:' mpi_bad.log)"
[ -e bad.mp4 ] || [ -e bad.png ] && fail "a refused run wrote its output"
cat > keys.json <<EOF
{ "objects": [ { "type": "model", "path": "$FLY", "camera": 4 } ] }
EOF
expect_refusal "keys.json: objects[0].camera: no camera 4" "$RAYFARM" still keys.json -o bad.png
cat > keys.json <<EOF
{ "objects": [ { "type": "model", "path": "$FLY", "scene": 3 } ] }
EOF
expect_refusal --exact "$FLY: objects[0].scene: no scene 3 (the file has 2 scenes)" "$RAYFARM" still keys.json -o bad.png
# The scene file's keys give what the options give.
cat > keys.json <<EOF
{ "objects": [ { "type": "model", "path": "$FLY", "scene": 0, "camera": 0 } ] }
EOF
"$RAYFARM" info --json "$FLY" --scene 0 > spare.json 2>/dev/null || fail "info --scene 0"
python3 -c "import json,sys; d=json.load(open('spare.json')); assert [s['drawn'] for s in d['scenes']]==[True,False] and d['camera_views'][0]['node_name']=='SpareCam', d" ||
    fail "info --scene 0"
echo ok
