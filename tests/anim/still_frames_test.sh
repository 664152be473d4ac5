#!/usr/bin/env bash
# rayfarm still --frame/--time end to end on scenes/whitted.json (31-frame orbit):
#   the default still is frame 0; --time 0.5 is frame 15 to the byte; frames differ along the
#   orbit; a frame outside the timeline is one usage-error line with exit status 2.
set -u
rayfarm=$1 src=$2 out=$3
mkdir -p "$out"
scene=$src/scenes/whitted.json
fail() { echo "FAIL: $*"; exit 1; }
still() { "$rayfarm" still "$scene" --size 96x54 --threads 1 "$@" 2>/dev/null; }

still -o "$out/default.png" || fail "default still"
still -o "$out/f0.png" --frame 0 || fail "--frame 0"
still -o "$out/f15.png" --frame 15 || fail "--frame 15"
still -o "$out/t05.png" --time 0.5 || fail "--time 0.5"
still -o "$out/f30.png" --frame 30 || fail "--frame 30"
cmp -s "$out/default.png" "$out/f0.png" || fail "the default still is not frame 0"
cmp -s "$out/f15.png" "$out/t05.png" || fail "--time 0.5 differs from --frame 15 (t = 15/30)"
cmp -s "$out/f0.png" "$out/f15.png" && fail "frame 15 of the orbit looks like frame 0"

err=$("$rayfarm" still "$scene" --size 96x54 -o "$out/bad.png" --frame 31 2>&1 >/dev/null)
status=$?
[ "$status" -eq 2 ] || fail "--frame 31: exit status $status, expected 2"
[ "$(printf '%s\n' "$err" | wc -l)" -eq 1 ] || fail "--frame 31: expected one line, got: $err"
case "$err" in
  "rayfarm: error: --frame: expected an integer from 0 to 30"*) ;;
  *) fail "--frame 31: unexpected message: $err" ;;
esac
[ -e "$out/bad.png" ] && fail "--frame 31 wrote an image"

# --animation on a skinned model (assimp's simple_skin, one clip): the pose at --time 1 differs
# from --time 0; by index 0 it is the same clip; an unknown name is one line listing the clips.
skin=/usr/share/assimp/models/glTF2/simple_skin/simple_skin.gltf
if [ -f "$skin" ]; then
    "$rayfarm" still "$skin" --size 64x48 --threads 1 --time 1 -o "$out/skin_t1.png" 2>/dev/null || fail "simple_skin --time 1"
    "$rayfarm" still "$skin" --size 64x48 --threads 1 --time 1 --animation 0 -o "$out/skin_a0.png" 2>/dev/null || fail "--animation 0"
    cmp -s "$out/skin_t1.png" "$out/skin_a0.png" || fail "--animation 0 is not the default clip"
    all=$("$rayfarm" still "$skin" --size 64x48 -o "$out/skin_bad.png" --animation walk 2>&1 >/dev/null)
    status=$?
    [ "$status" -eq 2 ] || fail "--animation walk: exit status $status, expected 2"
    err=$(printf '%s\n' "$all" | grep -v '^rayfarm: note: ')  # the loader's notes come first
    [ "$(printf '%s\n' "$err" | wc -l)" -eq 1 ] || fail "--animation walk: expected one error line, got: $all"
    case "$err" in
      "rayfarm: error: $skin: --animation: no animation named \"walk\" (simple_skin.gltf has 1: 0 \"\")") ;;
      *) fail "--animation walk: unexpected message: $err" ;;
    esac
    [ -e "$out/skin_bad.png" ] && fail "--animation walk wrote an image"
fi
echo "ok"
