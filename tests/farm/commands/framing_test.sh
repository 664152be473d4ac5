#!/usr/bin/env bash
# The default turntable of a bare glTF model through the CLI: `render --background transparent`
# keeps RGBA PNG frames, and from their alpha (decoded by FFmpeg) the model spans at least 85 % of
# the image's width or height in its widest frame and touches the border in no frame, at a
# landscape and at a portrait --size (the framing fits the picture's own aspect ratio).
# Usage: framing_test.sh RAYFARM WORK_DIR
set -euo pipefail
RAYFARM=$1 WORK=$2
ENGINE=/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb
fail() { echo "FAIL: $*" >&2; exit 1; }
[ -f "$ENGINE" ] || fail "$ENGINE missing (package assimp-testmodels)"
rm -rf "$WORK"
mkdir -p "$WORK"

for size in 128x72 54x96; do
    w=${size%x*} h=${size#*x}
    "$RAYFARM" render "$ENGINE" --size "$size" --background transparent -o "$WORK/$size.mov" \
        --frames-dir "$WORK/$size" 2>"$WORK/$size.log" || { cat "$WORK/$size.log"; fail "render $size"; }
    ffmpeg -v error -i "$WORK/$size/frame_%06d.png" -vf alphaextract -f rawvideo -pix_fmt gray "$WORK/$size.alpha"
    python3 - "$WORK/$size.alpha" "$w" "$h" "$size" <<'EOF' || fail "framing at $size"
import sys
data, w, h, size = open(sys.argv[1], "rb").read(), int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
frames = len(data) // (w * h)
assert frames == 120, f"expected 120 frames, decoded {frames}"
widest, clipped = 0.0, []
for f in range(frames):
    a = data[f * w * h:(f + 1) * w * h]
    cols = [x for x in range(w) if any(a[y * w + x] for y in range(h))]
    rows = [y for y in range(h) if any(a[y * w:(y + 1) * w])]
    if not cols:
        clipped.append(f"{f} (empty)")
        continue
    widest = max(widest, (cols[-1] - cols[0] + 1) / w, (rows[-1] - rows[0] + 1) / h)
    if cols[0] == 0 or rows[0] == 0 or cols[-1] == w - 1 or rows[-1] == h - 1:
        clipped.append(str(f))
print(f"{size}: widest frame fills {widest:.3f} of the width or height; frames on the border: {len(clipped)}")
ok = widest >= 0.85 and not clipped
if clipped:
    print("  clipped frames:", " ".join(clipped[:20]))
sys.exit(0 if ok else 1)
EOF
done
echo "ok"
