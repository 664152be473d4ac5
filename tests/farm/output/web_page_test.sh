#!/usr/bin/env bash
# examples/web_turntable.sh end to end in headless Chromium: the WebM with alpha over the page's
# colour. The page's first frame (no poster, no autoplay) is screenshotted and compared with
# frame 0's PNG laid over the page colour: around the model the page colour shows through, the
# model's pixels are its own.
# Usage: web_page_test.sh RAYFARM SOURCE_DIR WORK_DIR
set -euo pipefail
RAYFARM=$1 SRC=$2 WORK=$3
fail() { echo "FAIL: $*" >&2; exit 1; }
command -v chromium >/dev/null || fail "chromium missing (Debian package chromium; tests/install-deps.sh)"
rm -rf "$WORK" && mkdir -p "$WORK"
OUT_DIR="$WORK" RAYFARM_BIN="$RAYFARM" SIZE=160x120 FRAMES=0:5 SPP=4 PAGE_COLOUR='#2a9d8f' \
    bash "$SRC/examples/web_turntable.sh" > "$WORK/example.log" 2>&1 || { cat "$WORK/example.log"; fail "web_turntable.sh failed"; }
[ -f "$WORK/turntable_page.html" ] || fail "no page written"
cd "$WORK"
timeout 120 chromium --headless --no-sandbox --disable-gpu --hide-scrollbars --force-device-scale-factor=1 \
    --autoplay-policy=no-user-gesture-required --virtual-time-budget=5000 --window-size=200,160 \
    --screenshot="$WORK/shot.png" "file://$WORK/turntable_page.html?still" > chromium.log 2>&1 || { cat chromium.log; fail "chromium failed"; }
[ -f shot.png ] || fail "no screenshot"
python3 - <<'PY' || fail "the page does not show the WebM's alpha over its colour"
import math, subprocess, sys
def rgba(path):
    return subprocess.run(["ffmpeg", "-v", "error", "-i", path, "-f", "rawvideo", "-pix_fmt", "rgba", "-"],
                          check=True, stdout=subprocess.PIPE).stdout
shot, frame = rgba("shot.png"), rgba("turntable_page/frames/frame_000000.png")
SW, W, H, page = 200, 160, 120, (0x2a, 0x9d, 0x8f)
se = n = around = model = 0
for y in range(H):
    for x in range(W):
        s = shot[4 * (y * SW + x):4 * (y * SW + x) + 3]
        f = frame[4 * (y * W + x):4 * (y * W + x) + 4]
        want = [(f[c] * f[3] + page[c] * (255 - f[3]) + 127) // 255 for c in range(3)]
        se += sum((s[c] - want[c]) ** 2 for c in range(3)); n += 3
        if f[3] == 0: around += max(abs(s[c] - page[c]) for c in range(3)) <= 3
        if f[3] == 255: model += max(abs(s[c] - f[c]) for c in range(3)) <= 24
# Issue 15: the anti-aliased edge (25-75% covered) composites as straight alpha, C·a + P·(1−a);
# had Chromium read the WebM as premultiplied it would show C + P·(1−a). Compared in luma, which
# 4:2:0 keeps at full resolution.
luma = lambda p: 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]
s_err, p_err = [], []
for i in range(W * H):
    f = frame[4 * i:4 * i + 4]
    if not (64 <= f[3] <= 192 and luma(f) >= 40):
        continue
    y, x = divmod(i, W)
    s = shot[4 * (y * SW + x):4 * (y * SW + x) + 3]
    a = f[3] / 255
    s_err.append(abs(luma(s) - luma([f[c] * a + page[c] * (1 - a) for c in range(3)])))
    p_err.append(abs(luma(s) - luma([min(255, f[c] + page[c] * (1 - a)) for c in range(3)])))
edge_ok = len(s_err) >= 8 and sum(s_err) / len(s_err) <= 12 and sum(p_err) > 2 * sum(s_err)
print("edge: %d pixels 25-75%% covered: luma off the straight composite by %.1f levels (off a premultiplied one: %.1f)"
      % (len(s_err), sum(s_err) / max(1, len(s_err)), sum(p_err) / max(1, len(p_err))))
transparent = sum(frame[4 * i + 3] == 0 for i in range(W * H))
opaque = sum(frame[4 * i + 3] == 255 for i in range(W * H))
psnr = 10 * math.log10(255 * 255 * n / max(se, 1))
# Stated thresholds: the page colour within 3 levels on 99% of the transparent pixels, the
# model's colour within 24 levels on 90% of its opaque pixels, 25 dB over the whole video area.
print("page colour around the model: %d of %d; model pixels its own: %d of %d; PSNR %.1f dB" % (around, transparent, model, opaque, psnr))
outside = shot[4 * (130 * SW + 180):4 * (130 * SW + 180) + 3]  # beyond the video: the page itself
sys.exit(not (around >= 0.99 * transparent and model >= 0.90 * opaque and psnr >= 25 and tuple(outside) == page
              and transparent > 1000 and opaque > 1000 and edge_ok))
PY
echo ok
