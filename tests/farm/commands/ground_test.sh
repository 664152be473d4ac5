#!/usr/bin/env bash
# --ground shadow end to end: the glTF box turntable over a transparent background keeps RGBA PNG
# frames whose ground pixels are black with the shadow as alpha (clear ground: alpha 0); the
# frames are bit-identical under mpirun -np 3 (pixel mode) and -np 1; a scene file's
# "ground": "shadow" gives the same picture as --ground shadow; bad values are one error line
# and exit 2. Usage: ground_test.sh RAYFARM SOURCE_DIR WORK_DIR
set -euo pipefail
RAYFARM=$1 SRC=$2 WORK=$3
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
BOX=/usr/share/assimp/models/glTF2/BoxTextured-glTF-Binary/BoxTextured.glb
fail() { echo "FAIL: $*" >&2; exit 1; }
[ -f "$BOX" ] || fail "$BOX missing (package assimp-testmodels)"
rm -rf "$WORK"
mkdir -p "$WORK"
cd "$WORK"

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

# 1. Ranks: np 1 (frame mode) and np 3 (pixel mode) write the same PNG frames, byte for byte.
for np in 1 3; do
    mode=frame
    [ "$np" = 3 ] && mode=pixel
    mpirun --oversubscribe -np "$np" "$RAYFARM" render "$BOX" --ground shadow --background transparent --size 96x54 \
        --frames 0:5 --mode "$mode" -o "np$np.mov" --frames-dir "np$np" 2>"np$np.log" || { cat "np$np.log"; fail "render np $np"; }
done
for f in np1/frame_*.png; do
    cmp -s "$f" "np3/$(basename "$f")" || fail "$(basename "$f") differs between np 1 and np 3"
done
[ "$(ls np1/frame_*.png | wc -l)" = 6 ] || fail "expected 6 frames"

# 2. Alpha: every frame has shadow pixels (0 < alpha < 255, colour black) below the box, and
#    clear ground or sky (alpha 0); without --ground the same frames have no partial alpha there.
"$RAYFARM" render "$BOX" --background transparent --size 96x54 --frames 0:5 -o bare.mov --frames-dir bare 2>bare.log ||
    { cat bare.log; fail "render without ground"; }
for d in np1 bare; do
    ffmpeg -v error -i "$d/frame_%06d.png" -f rawvideo -pix_fmt rgba "$d.rgba"
done
python3 - np1.rgba bare.rgba 96 54 <<'EOF' || fail "shadow alpha"
import sys
g, b, w, h = open(sys.argv[1], "rb").read(), open(sys.argv[2], "rb").read(), int(sys.argv[3]), int(sys.argv[4])
n = w * h * 4
assert len(g) == len(b) == 6 * n, (len(g), len(b))
for f in range(6):
    G, B = g[f * n:(f + 1) * n], b[f * n:(f + 1) * n]
    shadow = strong = clear = 0
    for i in range(0, n, 4):
        ga, ba = G[i + 3], B[i + 3]
        if ba == 0 and ga > 0:  # ground that the bare film shows as nothing
            shadow += 1
            strong += ga >= 128  # the key light's shadow, not only contact darkening
            if max(G[i:i + 3]) > 0:
                sys.exit(f"frame {f}: a shadow pixel has colour {tuple(G[i:i + 3])}, expected black")
        if ba == 0 and ga == 0:
            clear += 1
        if ba == 255 and G[i:i + 4] != B[i:i + 4]:
            sys.exit(f"frame {f}: a model pixel changed with the ground")
    print(f"frame {f}: {shadow} ground pixels with alpha > 0 ({strong} at least 128), {clear} clear")
    # The box fills the frame, so the ground shows below and beside it, and the sky above.
    if strong < 20 or clear < w * h // 10:
        sys.exit(f"frame {f}: {strong} strong shadow pixels, {clear} clear ones")
EOF

# 3. The scene file's key gives what the option gives.
cat > box_ground.json <<EOF
{ "objects": [ { "type": "model", "path": "$BOX" } ],
  "camera": { "eye": [1.2, 1.0, 2.0], "target": [0, 0, 0], "fov": 45 },
  "lights": [ { "type": "directional", "direction": [-0.5, -1, -0.3] } ],
  "background": [0.6, 0.6, 0.6], "render": { "width": 64, "height": 48 }, "ground": "shadow" }
EOF
sed 's/, "ground": "shadow"//' box_ground.json > box_plain.json
"$RAYFARM" still box_ground.json -o key.png 2>/dev/null || fail "still with \"ground\""
"$RAYFARM" still box_plain.json --ground shadow -o option.png 2>/dev/null || fail "still --ground shadow"
"$RAYFARM" still box_plain.json -o plain.png 2>/dev/null || fail "still without ground"
cmp -s key.png option.png || fail "\"ground\": \"shadow\" and --ground shadow differ"
cmp -s key.png plain.png && fail "the ground changed nothing"
"$RAYFARM" still box_ground.json --ground none -o none.png 2>/dev/null || fail "still --ground none"
cmp -s none.png plain.png || fail "--ground none does not take the scene's ground away"

# 4. Refusals.
expect_usage_error "--ground: expected shadow or none" "$RAYFARM" still "$BOX" --ground floor -o bad.png
sed 's/"ground": "shadow"/"ground": 5/' box_ground.json > bad.json
expect_usage_error "bad.json: ground: expected \"shadow\" or \"none\"" "$RAYFARM" still bad.json -o bad.png
[ -e bad.png ] && fail "a refused run wrote an image"
echo "ok"
