#!/usr/bin/env bash
# rayfarm still --camera N end to end: the glTF cameras of cameras/Cameras.gltf (0 perspective,
# 1 orthographic) give other views than the default framing and each other, and a camera the
# scene lacks is one error line with exit status 2.
set -u
rayfarm=$1 out=$2
model=/usr/share/assimp/models/glTF2/cameras/Cameras.gltf
mkdir -p "$out"
rm -f "$out"/*.png  # a previous run's pictures must not pass for this one's
fail() { echo "FAIL: $*"; exit 1; }
[ -f "$model" ] || fail "$model missing (package assimp-testmodels)"

"$rayfarm" still "$model" --size 64x36 -o "$out/default.png" 2>/dev/null || fail "default view"
"$rayfarm" still "$model" --size 64x36 -o "$out/cam0.png" --camera 0 2>/dev/null || fail "--camera 0"
cmp -s "$out/default.png" "$out/cam0.png" && fail "--camera 0 renders the default framing"
"$rayfarm" still "$model" --size 64x36 -o "$out/cam1.png" --camera 1 2>/dev/null || fail "--camera 1 (orthographic)"
cmp -s "$out/cam0.png" "$out/cam1.png" && fail "--camera 1 renders what --camera 0 does"

for bad in "$model --camera 2" "$model --camera 7"; do
  err=$("$rayfarm" still $bad --size 64x36 -o "$out/bad.png" 2>&1 >/dev/null | grep -v '^rayfarm: note:')
  status=${PIPESTATUS[0]}
  [ "$(printf '%s\n' "$err" | wc -l)" -eq 1 ] || fail "$bad: expected one error line, got: $err"
  case "$err" in
    "rayfarm: error: $model: --camera: no camera "*) ;;
    *) fail "$bad: unexpected message: $err" ;;
  esac
  [ -e "$out/bad.png" ] && fail "$bad wrote an image"
done
"$rayfarm" still "$model" --size 64x36 -o "$out/bad.png" --camera 7 >/dev/null 2>&1
[ $? -eq 2 ] || fail "--camera 7: exit status is not 2"
echo "ok"
