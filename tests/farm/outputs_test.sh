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
    out=box.$ext fdir=box.frames
    rm -rf "$out" "$fdir" sheet.png poster.png
    mpi "$np" render "$BOX" -o "$out" --mode "$mode" --size 96x72 --frames 0:5 --spp 4 --background transparent \
        --contact-sheet sheet.png --poster poster.png --poster-frame 2 2> run.log || { cat run.log; fail "render failed"; }
    read -r frames w h rate < <(probe "$out")
    [ "$frames $w $h" = "6 96 72" ] || fail "$out: $frames frames ${w}x$h, expected 6 96x72"
    if [ "$ext" = gif ]; then  # GIF delays are centiseconds: 3 or 4 at 30 fps
        dur=$(ffprobe -v error -show_entries format=duration -of csv=p=0 "$out")
        python3 -c "import sys; sys.exit(abs(float(sys.argv[1]) - 0.2) > 0.021)" "$dur" || fail "$out lasts $dur s, expected 0.2"
        read -r _ colours _ distinct _ fixed _ loop < <(python3 "$SRC/tests/farm/gif_check.py" "$out")
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
    read -r _ n _ psnr a0 a1 < <(python3 "$SRC/tests/farm/video_check.py" "$out" "$fdir" 0 96x72 "${decoder[@]}" --at 0,0 --at 48,36)
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
        rm -rf "$out.webm" "$out.frames"  # the default frames directory: OUT.frames
        mpi "$np" render "$SRC/tests/farm/data/turntable_small.json" -o "$out.webm" --mode "$mode" --size 64x48 \
            --background transparent --frames-format exr 2> "$out.log" || { cat "$out.log"; fail "np $np $mode failed"; }
        sums=$( (cd "$out.frames" && md5sum frame_*.png frame_*.exr) )
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
    wait_for_pngs int.frames 3 120
    kill -"$sig" "$pid"
    set +e; wait "$pid"; set -e
    grep -q "rayfarm: interrupted (SIG$sig): the video int.$ext holds .* (playable)" int.log || { cat int.log; fail "no interrupt message naming SIG$sig"; }
    grep -A1 "rayfarm: interrupted" int.log | grep -q "^rayfarm: to resume: mpirun .*--resume$" || { cat int.log; fail "no resume command"; }
    read -r frames w h rate < <(probe "int.$ext")
    kept=$(ls int.frames | grep -c '^frame_.*\.png$')
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
    ;;
*) fail "unknown case $CASE" ;;
esac
echo ok
