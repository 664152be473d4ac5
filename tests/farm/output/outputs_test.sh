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

mpi() { local np=$1; shift; mpirun --oversubscribe -np "$np" "$RAYFARM" "$@"; }

probe() {  # file -> "frames width height rate"
    ffprobe -v error -select_streams v:0 -count_frames \
        -show_entries stream=nb_read_frames,width,height,r_frame_rate -of default=nw=1 "$1" |
        awk -F= '{v[$1]=$2} END {print v["nb_read_frames"], v["width"], v["height"], v["r_frame_rate"]}'
}

# Stated thresholds: min PSNR (dB) over frames of the decoded video against the PNG frames,
# premultiplied RGBA, at 96x72 with a transparent background (video_check.py).
psnr_min() { case "$1" in webm) echo 30 ;; mov) echo 45 ;; gif) echo 24 ;; mp4) echo 30 ;; esac; }

wait_for_pngs() {  # dir count timeout-seconds
    local t=0
    while [ "$(ls "$1" 2>/dev/null | grep -c '^frame_.*\.png$')" -lt "$2" ]; do
        sleep 0.1; t=$((t + 1)); [ $t -lt $(($3 * 10)) ] || fail "fewer than $2 frames in $1 after $3 s"
    done
}

at_least() { python3 -c "import sys; sys.exit(not float(sys.argv[1]) >= float(sys.argv[2]))" "$1" "$2"; }

# Pixel (x, y) of an image as "r g b a" (any format FFmpeg reads; frame N of a video).
pixel() {  # file x y [frame]
    ffmpeg -v error -i "$1" -vf "select=eq(n\,${4:-0}),format=rgba,crop=1:1:$2:$3" -frames:v 1 -f rawvideo - |
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
format)
    # One format end to end: EXT NP MODE. The glTF box turntable, 6 frames, transparent.
    ext=$1 np=$2 mode=$3
    out=box.$ext fdir=box.$ext.frames
    rm -rf "$out" "$fdir" sheet.png poster.png
    mpi "$np" render "$BOX" -o "$out" --mode "$mode" --size 96x72 --frames 0:5 --spp 4 --background transparent \
        --contact-sheet sheet.png --poster poster.png --poster-frame 2 2> run.log || { cat run.log; fail "render failed"; }
    read -r frames w h rate < <(probe "$out")
    [ "$frames $w $h" = "6 96 72" ] || fail "$out: $frames frames ${w}x$h, expected 6 96x72"
    if [ "$ext" = gif ]; then  # GIF delays are centiseconds: 3 or 4 at 30 fps
        dur=$(ffprobe -v error -show_entries format=duration -of csv=p=0 "$out")
        python3 -c "import sys; sys.exit(abs(float(sys.argv[1]) - 0.2) > 0.021)" "$dur" || fail "$out lasts $dur s, expected 0.2"
        read -r _ colours _ distinct _ fixed _ loop < <(python3 "$SRC/tests/farm/output/gif_check.py" "$out")
        [ "$fixed" = no ] || fail "$out uses a fixed palette"
        [ "$distinct" -ge 32 ] || fail "$out palette has only $distinct colours"
        [ "$loop" = 0 ] || fail "$out does not loop for ever (loop $loop)"
    else
        [ "$rate" = 30/1 ] || fail "$out rate $rate, expected 30/1"
    fi
    decoder=() want_pix=""
    case "$ext" in
        webm) decoder=(--decoder libvpx-vp9) want_pix=yuva420p ;;
        mov) want_pix=yuva444p ;;
        gif) want_pix=bgra ;;
        mp4) want_pix=yuv420p ;;
    esac
    # The decoder's pixel format (WebM: libvpx's decoder, which reads the alpha side data).
    dec=()
    [ "$ext" = webm ] && dec=(-c:v libvpx-vp9)
    pix=$(ffmpeg -hide_banner "${dec[@]}" -i "$out" -frames:v 1 -f null - 2>&1 | grep -m1 "Stream #0:0.*: Video" |
          sed -E 's/.*Video: [^,]*, ([a-z0-9]+).*/\1/')
    case "$pix" in "$want_pix"*) ;; *) fail "$out pixel format $pix, expected $want_pix" ;; esac
    if [ "$ext" = webm ]; then
        [ "$(ffprobe -v error -show_entries stream_tags=alpha_mode -of csv=p=0 "$out")" = 1 ] || fail "$out has no AlphaMode"
    fi
    # MP4 has no alpha: compared with the frames laid over the glTF default background colour
    # (black: a bare model's world is the studio environment, and behind it nothing).
    [ "$ext" = mp4 ] && decoder+=(--over 0,0,0)
    read -r _ n _ psnr a0 a1 < <(python3 "$SRC/tests/farm/output/video_check.py" "$out" "$fdir" 0 96x72 "${decoder[@]}" --at 0,0 --at 48,36)
    [ "$n" = 6 ] || fail "$out decodes to $n frames"
    if [ "$ext" = mp4 ]; then  # no alpha: laid over the glTF default background colour (black)
        [ "$a0 $a1" = "alpha@0,0=255 alpha@48,36=255" ] || fail "$out: $a0 $a1"
        read -r r g b a < <(pixel "$out" 0 0)
        python3 -c "import sys; sys.exit(max(abs(int(v) - 0) for v in sys.argv[1:]) > 3)" "$r" "$g" "$b" ||
            fail "$out background $r $g $b, expected about 0"
        at_least "$psnr" "$(psnr_min "$ext")" || fail "$out: min PSNR $psnr dB against the flattened frames < $(psnr_min "$ext") dB"
    else
        [ "$a0" = "alpha@0,0=0" ] || fail "$out: background pixel not transparent ($a0)"
        [ "$a1" = "alpha@48,36=255" ] || fail "$out: model pixel not opaque ($a1)"
        at_least "$psnr" "$(psnr_min "$ext")" || fail "$out: min PSNR $psnr dB < $(psnr_min "$ext") dB"
    fi
    [ "$(ffprobe -v error -show_entries stream=pix_fmt -of csv=p=0 "$fdir/frame_000000.png")" = rgba ] || fail "PNG frames lack alpha"
    # 6 frames of 96x72: 4 to a row, full-size thumbnails, 4 px padding, 7 px labels: 404x178.
    [ "$(ffprobe -v error -show_entries stream=width,height -of csv=p=0 sheet.png)" = 404,178 ] || fail "contact sheet size"
    cmp -s <(ffmpeg -v error -i poster.png -f rawvideo -pix_fmt rgba -) \
           <(ffmpeg -v error -i "$fdir/frame_000002.png" -f rawvideo -pix_fmt rgba -) || fail "poster is not frame 2"
    echo "$out ($np rank(s), $mode): 6 frames 96x72, $pix, min PSNR $psnr dB, $a0 $a1"
    ;;
modes-alpha)
    # Pixel and frame mode at 1-3 ranks give the same RGBA PNG and EXR frames and the same WebM.
    ref=""
    for run in "1 frame" "3 pixel" "2 pixel" "3 frame"; do
        read -r np mode <<< "$run"
        out=m_${np}_$mode
        rm -rf "$out.webm" "$out.webm.frames"  # the default frames directory: OUT.frames
        mpi "$np" render "$SRC/tests/farm/data/turntable_small.json" -o "$out.webm" --mode "$mode" --size 64x48 \
            --background transparent --frames-format exr 2> "$out.log" || { cat "$out.log"; fail "np $np $mode failed"; }
        sums=$( (cd "$out.webm.frames" && md5sum frame_*.png frame_*.exr) )
        [ "$(echo "$sums" | grep -c exr)" = 6 ] || fail "np $np $mode: $(echo "$sums" | grep -c exr) EXR frames, expected 6"
        vid=$(ffmpeg -v error -c:v libvpx-vp9 -i "$out.webm" -f framemd5 -pix_fmt rgba - | grep -v '^#' | awk -F, '{print $NF}')
        if [ -z "$ref" ]; then ref="$sums" refvid="$vid"; continue; fi
        [ "$sums" = "$ref" ] || fail "np $np $mode: PNG/EXR frames differ from np 1 frame mode"
        [ "$vid" = "$refvid" ] || fail "np $np $mode: decoded WebM differs from np 1 frame mode"
    done
    echo "modes-alpha: PNG, EXR and WebM identical at np 1-3 in pixel and frame mode"
    ;;
interrupt)
    # Ctrl-C (or SIG=TERM: scancel, a shutdown): every format is playable with the frames done,
    # the contact sheet holds only those, and --resume gives the same file as a run never
    # interrupted. EXT NP MODE [SIG]
    ext=$1 np=$2 mode=$3 sig=${4:-INT}
    # Many short frames (a frame in progress finishes before the run stops, and mpirun sends
    # SIGKILL about a second after SIGTERM), each slow enough (64 spp) that the run is still
    # going when the third frame lands: at 16 spp all 60 were done before the signal.
    args=(render "$BOX" --size 96x72 --frames 0:59 --spp 64 --mode "$mode" --background transparent)
    rm -rf int.* ref.* sheet.png
    mpirun --oversubscribe -np "$np" "$RAYFARM" "${args[@]}" -o "int.$ext" --contact-sheet sheet.png 2> int.log &
    pid=$!
    wait_for_pngs int.$ext.frames 3 120
    if [ "$sig" = TERM ]; then
        # scancel signals every process of the job, the ranks as well as mpirun (which also
        # passes it on). Signalling mpirun alone once went unanswered in a CI run under load:
        # the 60-frame film finished with no interrupt.
        pkill -TERM -P "$pid" || true
    fi
    kill -"$sig" "$pid" 2>/dev/null || true  # mpirun may already be gone: the checks below tell
    set +e; wait "$pid"; set -e
    # mpirun passes a Ctrl-C on to the ranks as SIGTERM.
    named=SIG$sig
    [ "$sig" = INT ] && named="SIG(INT|TERM)"
    grep -Eq "rayfarm: interrupted \($named\): the video int\.$ext holds .* \(playable\)" int.log || { cat int.log; fail "no interrupt message naming $named"; }
    grep -A1 "rayfarm: interrupted" int.log | grep -q "^rayfarm: to resume: mpirun .*--resume$" || { cat int.log; fail "no resume command"; }
    read -r frames w h rate < <(probe "int.$ext")
    kept=$(ls int.$ext.frames | grep -c '^frame_.*\.png$')
    [ "$frames" -ge 1 ] && [ "$frames" -lt 60 ] && [ "$frames" -le "$kept" ] || fail "partial $ext has $frames frames ($kept kept)"
    # The sheet's 12 cells (frames round(i*59/11)): a thumbnail exactly for frames in the video.
    python3 - "$frames" <<'PY' || fail "contact sheet after the interrupt"
import subprocess, sys
done = int(sys.argv[1])
raw = subprocess.run(["ffmpeg", "-v", "error", "-i", "sheet.png", "-f", "rawvideo", "-pix_fmt", "rgb24", "-"],
                     check=True, stdout=subprocess.PIPE).stdout
W = 404
for i in range(12):
    f = round(i * 59 / 11)
    x, y = 4 + (i % 4) * 100 + 48, 4 + (i // 4) * 87 + 36
    grey = raw[3 * (y * W + x):3 * (y * W + x) + 3] == bytes([48, 48, 48])
    if grey == (f < done):
        sys.exit("cell of frame %d: %s, but the video holds %d frames" % (f, "empty" if grey else "filled", done))
PY
    echo "interrupt ($ext, np $np $mode, SIG$sig): partial file plays $frames frames, contact sheet holds exactly those"
    mpi "$np" "${args[@]}" -o "int.$ext" --resume 2> resume.log || { cat resume.log; fail "resume failed"; }
    read -r frames w h rate < <(probe "int.$ext")
    [ "$frames" = 60 ] || fail "resumed $ext has $frames frames"
    "$RAYFARM" "${args[@]}" -o "ref.$ext" 2> ref.log || fail "reference run failed"
    if [ "$ext" = gif ]; then  # the palette comes from all frames: the same file byte for byte
        cmp -s "int.$ext" "ref.$ext" || fail "interrupted+resumed GIF differs from one uninterrupted run"
    else
        dec=()
        [ "$ext" = webm ] && dec=(-c:v libvpx-vp9)
        decoded() { ffmpeg -v error "${dec[@]}" -i "$1" -f framemd5 -pix_fmt rgba - | grep -v '^#' | awk -F, '{print $NF}'; }
        cmp -s <(decoded "int.$ext") <(decoded "ref.$ext") || fail "interrupted+resumed $ext decodes differently from one uninterrupted run"
    fi
    echo "interrupt ($ext): resumed film identical to an uninterrupted run"
    ;;
alpha-modes)
    # Issue 15: straight or premultiplied alpha, per format, at the anti-aliased edge of the box
    # (pixels 25-75% covered), where the two differ most. Each file of one frame is decoded with
    # FFmpeg and compared with the PNG frame (straight by the PNG specification) and the EXR frame
    # (premultiplied, "associated", by OpenEXR's):
    #   .png  straight, and consistent with the EXR: sRGB(EXR rgb / EXR a) = PNG rgb;
    #   .exr  premultiplied: its rgb are the PNG's linear colour times coverage;
    #   .mov  straight (yuva444p: FFmpeg's alpha pixel formats are straight; ProRes and MOV have
    #         no flag for premultiplied): decoded rgba = PNG rgba;
    #   .webm straight (the same yuva420p to libvpx; Chromium lays it over the page as straight:
    #         web_page_test.sh): alpha and luma (full resolution in 4:2:0) follow the PNG's;
    #   .gif  one bit: opaque where coverage >= 50% (paletteuse alpha_threshold 128) with the
    #         straight colour, transparent below.
    one=(render "$BOX" --size 96x72 --frames 4:4 --spp 16 --background transparent --tonemap clamp --exposure 0)
    rm -rf edge.*
    "$RAYFARM" "${one[@]}" -o edge.mov --frames-dir edge.frames --frames-format exr 2> edge.log || { cat edge.log; fail "render failed"; }
    for ext in webm gif; do
        "$RAYFARM" "${one[@]}" -o edge.$ext --no-frames 2>> edge.log || { cat edge.log; fail "render .$ext failed"; }
    done
    python3 - edge.frames/frame_000004.png edge.frames/frame_000004.exr edge.mov edge.webm edge.gif <<'PY' || fail "alpha at the edge"
import struct, subprocess, sys
png, exr, mov, webm, gif = sys.argv[1:]
W, H = 96, 72
def raw(args, fmt):
    return subprocess.run(["ffmpeg", "-v", "error"] + args + ["-frames:v", "1", "-f", "rawvideo", "-pix_fmt", fmt, "-"],
                          check=True, stdout=subprocess.PIPE).stdout
def rgba(path, dec=()):
    d = raw(list(dec) + ["-i", path], "rgba")
    return [tuple(d[4 * i:4 * i + 4]) for i in range(W * H)]
ref = rgba(png)
planes = raw(["-i", exr], "gbrapf32le")  # planes G, B, R, A
f = struct.unpack("<%df" % (4 * W * H), planes)
lin = [(f[2 * W * H + i], f[i], f[W * H + i], f[3 * W * H + i]) for i in range(W * H)]
def to_srgb8(v):
    v = min(max(v, 0.0), 1.0)
    return round(255 * (12.92 * v if v <= 0.0031308 else 1.055 * v ** (1 / 2.4) - 0.055))
def to_lin(c):
    c /= 255.0
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4
luma = lambda p: 0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]
edge = [i for i in range(W * H) if 64 <= ref[i][3] <= 192 and luma(ref[i]) >= 40]
if len(edge) < 8:
    sys.exit("only %d edge pixels 25-75%% covered and not dark" % len(edge))
def mean(xs): return sum(xs) / len(xs)
fails = []
def check(name, ok, what):
    print("alpha-modes: %-5s %s" % (name, what))
    if not ok: fails.append(name)
# PNG and EXR: the same pixel, straight and premultiplied.
a_err = mean([abs(lin[i][3] * 255 - ref[i][3]) for i in edge])
straight = mean([max(abs(to_srgb8(lin[i][c] / lin[i][3]) - ref[i][c]) for c in range(3)) for i in edge])
as_if = mean([max(abs(to_srgb8(lin[i][c]) - ref[i][c]) for c in range(3)) for i in edge])
check("png", a_err <= 1.0 and straight <= 2.0 and as_if > 10,
      "%d edge pixels: sRGB(EXR rgb/a) - PNG rgb %.2f levels (read as premultiplied: %.1f); alpha %.2f" % (len(edge), straight, as_if, a_err))
# (Where the straight colour stays below 0.9: the EXR is not tone-mapped, the PNG clamps at 1.)
lit = [i for i in edge if max(lin[i][c] / lin[i][3] for c in range(3)) < 0.9]
pre = mean([max(abs(lin[i][c] - to_lin(ref[i][c]) * ref[i][3] / 255) for c in range(3)) for i in lit]) if lit else 1
unpre = mean([max(abs(lin[i][c] - to_lin(ref[i][c])) for c in range(3)) for i in lit]) if lit else 0
check("exr", len(lit) >= 8 and pre <= 0.01 and unpre > 5 * pre,
      "%d of them below 0.9: EXR rgb - PNG linear x alpha %.4f (without the alpha: %.4f)" % (len(lit), pre, unpre))
m = rgba(mov)
s_err = mean([max(abs(m[i][c] - ref[i][c]) for c in range(3)) for i in edge])
p_err = mean([max(abs(m[i][c] - round(ref[i][c] * ref[i][3] / 255)) for c in range(3)) for i in edge])
a_err = max(abs(m[i][3] - ref[i][3]) for i in edge)
check("mov", s_err <= 4 and p_err > 3 * s_err and a_err <= 1,
      "decoded rgb - PNG straight %.2f levels (- premultiplied: %.1f); alpha within %d" % (s_err, p_err, a_err))
v = rgba(webm, ["-c:v", "libvpx-vp9"])
s_err = mean([abs(luma(v[i]) - luma(ref[i])) for i in edge])
p_err = mean([abs(luma(v[i]) - luma(ref[i]) * ref[i][3] / 255) for i in edge])
a_err = mean([abs(v[i][3] - ref[i][3]) for i in edge])
check("webm", s_err <= 12 and p_err > 2 * s_err and a_err <= 8,
      "decoded luma - PNG straight %.1f levels (- premultiplied: %.1f); alpha %.1f" % (s_err, p_err, a_err))
g = rgba(gif)
wrong_bit = [i for i in edge if (g[i][3] == 255) != (ref[i][3] >= 128) or g[i][3] not in (0, 255)]
opaque = [i for i in edge if ref[i][3] >= 128]
s_err = mean([abs(luma(g[i]) - luma(ref[i])) for i in opaque]) if opaque else 0
p_err = mean([abs(luma(g[i]) - luma(ref[i]) * ref[i][3] / 255) for i in opaque]) if opaque else 0
check("gif", not wrong_bit and opaque and s_err <= 16 and p_err > s_err,
      "%d of %d edge pixels with the wrong bit; opaque ones: luma - PNG straight %.1f (- premultiplied: %.1f)"
      % (len(wrong_bit), len(edge), s_err, p_err))
if fails:
    sys.exit("wrong alpha in: " + ", ".join(fails))
PY
    ;;
refusals)
    # Unsupported combinations: one line, exit 2, before rendering (no output file).
    for bad in "-o x.mov --crf 20:--crf: ProRes" "-o x.mp4 --codec vp9:--codec vp9" "-o x.gif --lossless:--lossless: a GIF" \
               "-o x.mov --preset hq --background transparent:ProRes carries alpha only" "-o x.avi:the output must be" \
               "-o x.webm --crf 64:--crf: expected" "-o x.webm --frames-format tiff:--frames-format: expected" \
               "-o x.gif --preset fast:for a GIF, the dither" "-o x.mp4 --poster p.jpg:expected a .png"; do
        args=${bad%%:*} pattern=${bad#*:}
        # shellcheck disable=SC2086
        expect_usage_error "$pattern" "$RAYFARM" render "$BOX" --size 32x24 --frames 0:1 $args
        for f in x.mov x.mp4 x.gif x.avi x.webm; do [ -e "$f" ] && fail "$args left $f"; done
    done
    # libavfilter is opened only for a GIF: a broken one on the library path is one error line
    # naming it, before the scene is shared or any frame rendered, and no GIF, alone or under
    # mpirun (the workers are told and stop at once); the other formats never touch it.
    avf=libavfilter.so.$(pkg-config --modversion libavfilter | cut -d. -f1)
    rm -rf x.gif.frames; mkdir -p fakelib && : > "fakelib/$avf"
    for np in 1 2; do
        launch=("$RAYFARM")
        [ "$np" = 1 ] || launch=(timeout 60 mpirun --oversubscribe -np "$np" -x LD_LIBRARY_PATH "$RAYFARM")
        set +e; LD_LIBRARY_PATH=$PWD/fakelib "${launch[@]}" render "$BOX" --size 32x24 --frames 0:1 -o x.gif 2> gif.log; rc=$?; set -e
        # One line of rayfarm's (mpirun adds its own banner about the exit status).
        [ "$rc" = 1 ] && [ "$(grep -c '^rayfarm:' gif.log)" = 1 ] && grep -q "^rayfarm: error: x.gif: cannot load $avf" gif.log ||
            { cat gif.log; fail "a broken libavfilter, np $np: exit $rc"; }
        [ -e x.gif ] && fail "a broken libavfilter left x.gif"
        [ -e x.gif.frames ] && fail "a broken libavfilter: frames folder made before the check"
    done
    rm -f nofilter.mp4  # not x.mp4: the refusals above check that none is ever left
    LD_LIBRARY_PATH=$PWD/fakelib "$RAYFARM" render "$BOX" --size 32x24 --frames 0:1 -o nofilter.mp4 --no-frames 2> mp4.log \
        || { cat mp4.log; fail "an MP4 needed libavfilter"; }
    [ -s nofilter.mp4 ] || fail "no MP4 without libavfilter"
    ;;
*) fail "unknown case $CASE" ;;
esac
echo ok
