#!/usr/bin/env bash
# Issue 47 #5: --background COLOUR is that colour in the output, exactly, and auto exposure
# meters the model alone. Stills and PNG frames hold the exact bytes where no model is (#ffffff,
# #00ff00, #336699, and a linear R,G,B); the video decoded back is within the YUV conversion's
# rounding; EXR frames hold the linear colour; the EV metered and the model's pixels are the same
# over two colours; --background transparent still gives alpha; under mpirun -np 3 in frame and
# pixel mode the frames are the same.
#   background_exact_test.sh RAYFARM OUT_DIR
set -euo pipefail
rayfarm=$1 out=$2
fail() { echo "FAIL: $*" >&2; exit 1; }
rm -rf "$out" && mkdir -p "$out" && cd "$out"
model=/usr/share/assimp/models/glTF2/BoxTextured-glTF-Binary/BoxTextured.glb
[ -f "$model" ] || { echo "SKIP: $model not installed (assimp-testmodels)"; exit 77; }
small=(--size 64x48 --spp 4)
# Pictures read back through FFmpeg's decoders (no Python imaging package needed).
cat > pic.py <<'PY'
import subprocess
def probe(path):
    return subprocess.run(["ffprobe", "-v", "error", "-select_streams", "v:0", "-show_entries", "stream=pix_fmt",
                           "-of", "csv=p=0", path], check=True, capture_output=True, text=True).stdout.strip()
def pixels(path, channels=3, w=64, h=48, frames=1):
    """Pixels of a picture (or the first `frames` frames of a video) as tuples, row by row."""
    raw = subprocess.run(["ffmpeg", "-v", "error", "-i", path, "-frames:v", str(frames), "-f", "rawvideo", "-pix_fmt",
                          "rgb24" if channels == 3 else "rgba", "-"], check=True, capture_output=True).stdout
    assert len(raw) == w * h * channels * frames, (path, len(raw))
    return [tuple(raw[i:i + channels]) for i in range(0, len(raw), channels)]
CORNERS = [0, 63, 64 * 47, 64 * 48 - 1]
PY

ev_of() { sed -n 's/.*auto exposure: EV \([-+][0-9.]*\),.*/\1/p' "$1"; }

# Stills over three colours and black: the background's pixels are the colour's own bytes.
for c in ffffff 00ff00 336699 000000; do
    "$rayfarm" still "$model" -o "still_$c.png" "${small[@]}" --background "#$c" --stats "still_$c.json" 2> "still_$c.err" ||
        { cat "still_$c.err"; fail "still #$c exited $?"; }
done
python3 - <<'PY' || fail "still: the background is not the exact colour, or the model differs between backgrounds"
import sys
from pic import *
bad = False
pics = {}
for c in ["ffffff", "00ff00", "336699", "000000"]:
    want = tuple(int(c[k:k + 2], 16) for k in (0, 2, 4))
    assert probe(f"still_{c}.png") == "rgb24", probe(f"still_{c}.png")
    px = pixels(f"still_{c}.png")
    pics[c] = px
    corners = [px[i] for i in CORNERS]
    exact = sum(1 for p in px if p == want)
    print(f"#{c}: corners {corners}, {exact} of {len(px)} pixels exactly {want}")
    if any(p != want for p in corners) or exact < len(px) // 5:
        bad = True
    if exact > len(px) * 0.95:
        print("  the model is missing"); bad = True
# The model's pixels: where neither background shows, the two stills agree (the box's texture
# mirrors no sky), so the exposure was metered on the model alone.
w, g = pics["ffffff"], pics["00ff00"]
both = [i for i in range(len(w)) if w[i] != (255, 255, 255) and g[i] != (0, 255, 0)]
inner = [i for i in both if all(0 <= i + d < len(w) and w[i + d] != (255, 255, 255) and g[i + d] != (0, 255, 0)
                                 for d in (-1, 1, -64, 64))]
diff = max(max(abs(a - b) for a, b in zip(w[i], g[i])) for i in inner)
print(f"model's inner pixels: {len(inner)}, largest difference between #ffffff and #00ff00: {diff}")
if len(inner) < 100 or diff != 0:
    bad = True
sys.exit(1 if bad else 0)
PY
ev_w=$(ev_of still_ffffff.err) ev_g=$(ev_of still_00ff00.err) ev_b=$(ev_of still_000000.err)
echo "metered EV: #ffffff $ev_w, #00ff00 $ev_g, #000000 $ev_b"
[ -n "$ev_w" ] && [ "$ev_w" = "$ev_g" ] && [ "$ev_w" = "$ev_b" ] || fail "the metered EV depends on the background: $ev_w, $ev_g, $ev_b"
# The same in --stats (exposure_ev), to the float.
python3 - <<'PY' || fail "--stats exposure_ev differs between backgrounds, or is missing"
import json
evs = {c: json.load(open(f"still_{c}.json")).get("exposure_ev") for c in ["ffffff", "00ff00", "336699", "000000"]}
print("--stats exposure_ev:", evs)
assert None not in evs.values() and len(set(evs.values())) == 1, evs
PY
echo "ok: stills over #ffffff, #00ff00, #336699 hold the exact colour; one EV ($ev_w) over every colour"

# A linear colour: the bytes are its sRGB encoding.
"$rayfarm" still "$model" -o lin.png "${small[@]}" --background 0.2,0.5,0.8 2>/dev/null || fail "still R,G,B exited $?"
python3 - <<'PY' || fail "still R,G,B: the background is not the sRGB encoding of the linear colour"
from pic import *
def enc(v):
    s = 12.92 * v if v <= 0.0031308 else 1.055 * v ** (1 / 2.4) - 0.055
    return round(s * 255)
want = tuple(enc(v) for v in (0.2, 0.5, 0.8))
got = pixels("lin.png")[0]
print("0.2,0.5,0.8 ->", got, "expected", want)
assert got == want
PY

# --background transparent is still alpha: the corners transparent, the model opaque.
"$rayfarm" still "$model" -o clear.png "${small[@]}" --background transparent 2>/dev/null || fail "still transparent exited $?"
python3 - <<'PY' || fail "--background transparent: no alpha"
from pic import *
assert probe("clear.png") == "rgba", probe("clear.png")
px = pixels("clear.png", 4)
assert px[0][3] == 0 and px[24 * 64 + 32][3] == 255, (px[0], px[24 * 64 + 32])
PY
echo "ok: a linear colour, and transparent"

# A film: PNG frames exact, the video within the YUV conversion's rounding, EXR frames linear.
check_film() {  # DIR VIDEO
    python3 - "$1" "$2" <<'PY'
import glob, sys
from pic import *
d, video = sys.argv[1], sys.argv[2]
want = (0x33, 0x66, 0x99)
frames = sorted(glob.glob(d + "/frame_*.png"))
assert len(frames) == 4, frames
for f in frames:
    px = pixels(f)
    got = [px[i] for i in CORNERS]
    assert all(p == want for p in got), (f, got)
# The video: every background pixel 4 pixels or more from the model, within the YUV
# conversion's rounding (--crf 0: x264 keeps the YUV planes whole, so only the conversion
# rounds; a lossy CRF adds its own ringing on such tiny frames).
v = pixels(video, frames=4)
worst = 0
for k, f in enumerate(frames):
    png = pixels(f)
    for y in range(48):
        for x in range(64):
            if all(png[yy * 64 + xx] == want for yy in range(max(0, y - 4), min(48, y + 5)) for xx in range(max(0, x - 4), min(64, x + 5))):
                p = v[k * 64 * 48 + y * 64 + x]
                worst = max(worst, max(abs(p[c] - want[c]) for c in range(3)))
print(f"{video}: PNG frames exact, video background within {worst} of {want}")
assert worst <= 3, worst
PY
}
"$rayfarm" render "$model" -o film.mp4 "${small[@]}" --frames 0:3 --background '#336699' --crf 0 --frames-format exr 2>film.err ||
    { cat film.err; fail "render exited $?"; }
check_film film.mp4.frames film.mp4 || fail "render: the background is not #336699 in the frames or the video"
python3 - <<'PY' || fail "EXR frames: the background is not the linear colour"
import subprocess, struct
raw = subprocess.run(["ffmpeg", "-v", "error", "-i", "film.mp4.frames/frame_000000.exr", "-f", "rawvideo", "-pix_fmt", "gbrapf32le", "-"],
                     check=True, capture_output=True).stdout
plane = 64 * 48 * 4
g, b, r = (struct.unpack_from("<f", raw, k * plane)[0] for k in range(3))
def dec(c):
    c /= 255
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4
want = [dec(v) for v in (0x33, 0x66, 0x99)]
print("EXR corner", (r, g, b), "linear of #336699", want)
assert all(abs(a - w) <= 2e-3 * max(w, 0.05) for a, w in zip((r, g, b), want))  # half floats
PY
echo "ok: a film's PNG frames, video and EXR frames"

if command -v mpirun >/dev/null; then
    for mode in frame pixel; do
        mpirun --oversubscribe -np 3 "$rayfarm" render "$model" -o "mpi_$mode.mp4" "${small[@]}" --frames 0:3 --background '#336699' \
            --crf 0 --mode "$mode" 2>"mpi_$mode.err" || { cat "mpi_$mode.err"; fail "mpirun -np 3 --mode $mode exited $?"; }
        check_film "mpi_$mode.mp4.frames" "mpi_$mode.mp4" || fail "mpirun -np 3 --mode $mode: the background is not #336699"
        cmp <(cd film.mp4.frames && cat frame_*.png) <(cd "mpi_$mode.mp4.frames" && cat frame_*.png) ||
            fail "mpirun -np 3 --mode $mode: frames differ from one process's"
    done
    echo "ok: mpirun -np 3, frame and pixel mode"
fi
echo "PASS"
