#!/usr/bin/env bash
# End-to-end tests of rayfarm's outputs (alpha, formats, contact sheet, poster), decoded back with
# FFmpeg's own tools. Usage: outputs_test.sh RAYFARM SOURCE_DIR WORK_DIR CASE
set -euo pipefail
RAYFARM=$1 SRC=$2 WORK=$3 CASE=$4
shift 4
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
BOX=/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf
mkdir -p "$WORK"
cd "$WORK"

fail() { echo "FAIL: $*" >&2; exit 1; }

# Pixel (x, y) of an image as "r g b a" (any format FFmpeg reads; frame N of a video).
pixel() {  # file x y [frame]
    ffmpeg -v error -i "$1" -vf "select=eq(n\,${4:-0}),crop=1:1:$2:$3,format=rgba" -frames:v 1 -f rawvideo - |
        od -An -tu1 | awk '{print $1, $2, $3, $4}'
}

# A usage error is exactly one line "rayfarm: error: ..." and exit status 2.
expect_usage_error() {  # pattern command...
    local pattern=$1 err status
    shift
    set +e
    err=$("$@" 2>&1 >/dev/null | grep -v '^rayfarm: note:')
    status=${PIPESTATUS[0]}
    set -e
    [ "$status" -eq 2 ] || fail "$*: exit status $status, expected 2 ($err)"
    [ "$(printf '%s\n' "$err" | wc -l)" -eq 1 ] || fail "$*: expected one error line, got: $err"
    case "$err" in rayfarm:\ error:\ *$pattern*) ;; *) fail "$*: unexpected message: $err" ;; esac
}

case "$CASE" in
still-background)
    "$RAYFARM" still "$BOX" --size 96x72 --spp 4 --background transparent -o clear.png 2>/dev/null || fail "transparent still"
    [ "$(ffprobe -v error -show_entries stream=pix_fmt -of csv=p=0 clear.png)" = rgba ] || fail "transparent PNG is not RGBA"
    read -r r g b a < <(pixel clear.png 0 0)
    [ "$a" -eq 0 ] || fail "background pixel alpha $a, expected 0"
    read -r r g b a < <(pixel clear.png 48 36)
    [ "$a" -eq 255 ] || fail "model pixel alpha $a, expected 255"
    # Clamp at 0 EV shows the colour as given (a glTF model's default, PBR Neutral after auto
    # exposure, tone-maps the background with the rest of the picture).
    "$RAYFARM" still "$BOX" --size 96x72 --background '#ff0000' --tonemap clamp --exposure 0 -o red.png 2>/dev/null || fail "coloured still"
    [ "$(ffprobe -v error -show_entries stream=pix_fmt -of csv=p=0 red.png)" = rgb24 ] || fail "opaque PNG is not RGB"
    read -r r g b a < <(pixel red.png 0 0)
    [ "$r $g $b" = "255 0 0" ] || fail "background #ff0000 gave $r $g $b"
    expect_usage_error "--background: expected transparent" "$RAYFARM" still "$BOX" --background pink -o bad.png
    expect_usage_error "--background: expected transparent" "$RAYFARM" still "$BOX" --background 1,0 -o bad.png
    [ -e bad.png ] && fail "a refused run wrote an image"
    ;;
*) fail "unknown case $CASE" ;;
esac
echo ok
