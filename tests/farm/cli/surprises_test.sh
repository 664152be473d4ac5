#!/usr/bin/env bash
# Issue 47 #7, the smaller surprises of a first hour, each checked through the real binary:
# --version (and in --stats), "did you mean" for options and commands, --threads range-checked,
# a directory as the scene, an odd --size with a video stated once and truly, info's cameras,
# distances and no "-0".
#   surprises_test.sh RAYFARM SOURCE_DIR OUT_DIR VERSION
set -euo pipefail
rayfarm=$1 src=$2 out=$3 version=$4
# shellcheck source=tests/lib/refusal.sh
source "$src/tests/lib/refusal.sh"
rm -rf "$out" && mkdir -p "$out" && cd "$out"
scene=$src/scenes/whitted.json
assimp=/usr/share/assimp/models/glTF2

# --version: the project's version, on stdout, exit 0; the stats file of still and render says it.
got=$("$rayfarm" --version) || fail "--version exited $?"
[ "$got" = "rayfarm $version" ] || fail "--version printed \"$got\", expected \"rayfarm $version\""
"$rayfarm" --help | grep -q -- "--version" || fail "rayfarm --help does not mention --version"
"$rayfarm" still "$scene" -o still.png --size 32x18 --stats still.json 2>/dev/null || fail "still exited $?"
"$rayfarm" render "$scene" -o film.mp4 --size 32x18 --frames 0:1 --no-frames --stats film.json 2>/dev/null || fail "render exited $?"
for f in still.json film.json; do
    python3 - "$f" "$version" <<'PY' || fail "$f: no \"version\": \"$version\""
import json, sys
sys.exit(0 if json.load(open(sys.argv[1])).get("version") == sys.argv[2] else 1)
PY
done
echo "ok: --version and the stats files' version"

# Did you mean: a slip of the keyboard in an option or a command names the closest; a word far
# from every option names none.
expect_refusal --exact "render: unknown option --szie; did you mean --size? (see rayfarm render --help)" \
    "$rayfarm" render "$scene" -o x.mp4 --szie 64x36
expect_refusal "unknown option --thread; did you mean --threads?" "$rayfarm" still "$scene" -o x.png --thread 2
expect_refusal "unknown option --animaton; did you mean --animation?" "$rayfarm" info "$assimp/cameras/Cameras.gltf" --animaton 0
expect_refusal "unknown option --enviroment; did you mean --environment?" "$rayfarm" still "$scene" -o x.png --enviroment x.hdr
expect_refusal --exact "render: unknown option --frobnicate (see rayfarm render --help)" "$rayfarm" render "$scene" -o x.mp4 --frobnicate
expect_refusal --prefix "unknown command \"rendr\"; did you mean render?" "$rayfarm" rendr "$scene" -o x.mp4
expect_refusal --prefix "unknown command \"stil\"; did you mean still?" "$rayfarm" stil "$scene"
expect_refusal --prefix "unknown command \"--verison\"; did you mean --version?" "$rayfarm" --verison
expect_refusal --exact "unknown command \"paint\" (expected render, still, report, view or info)" "$rayfarm" paint
echo "ok: did you mean"

# --threads: 1 to 4096 (left out: every core); 0 is refused, as is a negative count.
expect_refusal --exact '--threads: expected an integer from 1 to 4096, got "0"' "$rayfarm" render "$scene" -o x.mp4 --threads 0
expect_refusal --exact '--threads: expected an integer from 1 to 4096, got "0"' "$rayfarm" still "$scene" -o x.png --threads 0
expect_refusal --exact '--threads: expected an integer from 1 to 4096, got "-1"' "$rayfarm" still "$scene" -o x.png --threads -1
expect_refusal --exact '--threads: expected an integer from 1 to 4096, got "0"' "$rayfarm" report "$scene" --out rep --threads 0
expect_refusal --prefix '--target-psnr: expected dB above 0' "$rayfarm" report "$scene" --out rep --target-psnr -5
[ ! -e x.mp4 ] && [ ! -e x.png ] || fail "a refused run left its output"
echo "ok: numeric options range-checked"

# A directory as the scene is named as one, for each command.
mkdir -p scenedir
expect_refusal --exact "scenedir: is a directory, not a scene file (expected a .json, .gltf or .glb file)" "$rayfarm" still scenedir -o x.png
expect_refusal --prefix "scenedir: is a directory" "$rayfarm" render scenedir -o x.mp4
echo "ok: a directory as the scene"

# An odd size with a video: one note, naming the video's true (even) size; the kept frames'
# size only when frames are kept; the closing line gives the video's size, which it has.
"$rayfarm" render "$scene" -o odd.mp4 --size 65x37 --frames 0:1 --no-frames 2> odd.err || fail "odd size exited $?"
[ "$(grep -c '66x38' odd.err)" -eq 2 ] || fail "expected the note and the closing line to say 66x38: $(cat odd.err)"
[ "$(grep -c 'rayfarm: note:' odd.err)" -eq 1 ] || fail "expected one note: $(cat odd.err)"
grep -qi 'png\|kept frames' odd.err && fail "--no-frames keeps no frames, but the note talks about them: $(cat odd.err)"
grep -q 'wrote odd.mp4: 2 frames 66x38' odd.err || fail "the closing line does not give the video's size: $(cat odd.err)"
if command -v ffprobe >/dev/null; then
    size=$(ffprobe -v error -select_streams v:0 -show_entries stream=width,height -of csv=p=0:s=x odd.mp4)
    [ "$size" = "66x38" ] || fail "odd.mp4 is $size, not the 66x38 the lines say"
fi
"$rayfarm" render "$scene" -o oddkept.mp4 --size 65x37 --frames 0:1 2> oddkept.err || fail "odd size with frames exited $?"
grep -q 'rayfarm: note: the video is 66x38 .*; the kept frames are 65x37' oddkept.err || fail "no note on the kept frames' size: $(cat oddkept.err)"
echo "ok: odd sizes stated once and truly"

# info: an orthographic camera is one still --camera renders; the turntable's distance is in
# units from the target; no "-0" in text or JSON.
"$rayfarm" info "$assimp/cameras/Cameras.gltf" > cams.txt || fail "info exited $?"
grep -q 'not rendered' cams.txt && fail "info calls a camera not rendered: $(grep 'not rendered' cams.txt)"
grep -q '1 (no name): orthographic, a view 2 units high$' cams.txt || fail "the orthographic camera's line: $(grep orthographic cams.txt)"
grep -qE '^  camera [0-9.]+ units from the target \(' cams.txt || fail "the turntable's camera line: $(grep '  camera' cams.txt)"
"$rayfarm" info --json "$assimp/cameras/Cameras.gltf" | python3 -c '
import json, sys
c = json.load(sys.stdin)["cameras"]
sys.exit(0 if [x["rendered"] for x in c] == [True, True] else 1)' || fail "info --json: not every camera rendered"
"$rayfarm" still "$assimp/cameras/Cameras.gltf" --camera 1 --size 32x18 -o ortho.png 2>/dev/null || fail "still --camera 1 (orthographic) exited $?"
"$rayfarm" info "$src/tests/farm/data/cli/negative_zero.gltf" > negz.txt || fail "info exited $?"
grep -q 'bounds (0, 0, 0) to (1, 1, 0)' negz.txt || fail "bounds of a mesh at z = -0: $(grep bounds negz.txt)"
grep -qE -- '-0([^.0-9]|$)' negz.txt && fail "info prints -0: $(grep -E -- '-0([^.0-9]|$)' negz.txt)"
"$rayfarm" info --json "$src/tests/farm/data/cli/negative_zero.gltf" | grep -qE -- '-0(\.0+)?([^.0-9]|$)' && fail "info --json prints -0"
echo "ok: info's cameras, distances and no -0"
echo "surprises: all passed"
