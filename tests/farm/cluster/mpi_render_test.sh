#!/usr/bin/env bash
# End-to-end tests of `rayfarm render` under real `mpirun --oversubscribe`, checked with FFmpeg's
# own tools. Usage: mpi_render_test.sh RAYFARM SOURCE_DIR WORK_DIR CASE
#   modes SCENE [ARGS...]  np 1, 2, 3 × pixel, frame: PNGs bit-identical everywhere; every MP4
#                          has the timeline's frame count, size and rate and each frame is within
#                          PSNR_MIN dB of its PNG; a lossless MP4 decodes to the PNGs exactly
#   resume | interrupt | interrupt-slow | killed-master EXT | killed-worker | stalled-worker | suspend-all | suspend-master | signals | one-frame
#   | lost-worker MODE AT [RANKS] | lost-encoder MODE | lost-all | lost-master | lost-master-load STAGE NP | poison-frame
#   | odd-size | bad-output
set -euo pipefail
RAYFARM=$1 SRC=$2 WORK=$3 CASE=$4
shift 4
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
# Stated tolerance for libx264 at CRF 18 (yuv420p) against the PNG frames, RGB PSNR per frame.
PSNR_MIN=${PSNR_MIN:-30}
FLIGHT="$SRC/scenes/flight.json"
mkdir -p "$WORK"
cd "$WORK"

fail() { echo "FAIL: $*" >&2; exit 1; }
mpi() { local np=$1; shift; mpirun --oversubscribe -np "$np" "$RAYFARM" "$@"; }
# Runs that get signalled start mpirun directly in the background, so $! is mpirun itself.

probe() {  # file -> "frames width height rate"
    ffprobe -v error -select_streams v:0 -count_frames \
        -show_entries stream=nb_read_frames,width,height,r_frame_rate -of default=nw=1 "$1" |
        awk -F= '{v[$1]=$2} END {print v["nb_read_frames"], v["width"], v["height"], v["r_frame_rate"]}'
}

pngs_md5() { (cd "$1" && md5sum frame_*.png) ; }

# Decoded MP4 frames as RGB, one md5 per frame (crop to WxH first if given).
video_md5() {
    local vf=format=rgb24
    [ -n "${2:-}" ] && vf="crop=$2:0:0,format=rgb24"
    ffmpeg -v error -i "$1" -vf "$vf" -f framemd5 -pix_fmt rgb24 - | grep -v '^#' | awk -F, '{print $NF}'
}
pngs_rgb_md5() {  # the PNGs decoded the same way
    local first=$2
    ffmpeg -v error -start_number "$first" -i "$1/frame_%06d.png" -vf format=rgb24 -f framemd5 -pix_fmt rgb24 - |
        grep -v '^#' | awk -F, '{print $NF}'
}

# Minimum over frames of the RGB PSNR between the MP4 and the PNGs.
min_psnr() {  # mp4 framesdir first [crop WxH]
    local crop="" rate
    [ -n "${4:-}" ] && crop="format=rgb24,crop=$4:0:0,"
    # Pair frames by index: both streams get the video's rate.
    rate=$(ffprobe -v error -select_streams v:0 -show_entries stream=r_frame_rate -of csv=p=0 "$1")
    ffmpeg -v error -i "$1" -framerate "$rate" -start_number "$3" -i "$2/frame_%06d.png" \
        -lavfi "[0:v]${crop}format=rgb24[a];[1:v]format=rgb24[b];[a][b]psnr=stats_file=psnr.log" -f null - 
    awk '{for (i = 1; i <= NF; i++) if ($i ~ /^psnr_avg:/) { split($i, a, ":"); v = a[2] == "inf" ? 1e9 : a[2] + 0; if (min == "" || v < min) min = v } }
         END {print min}' psnr.log
}

rank_pid() {  # mpirun-pid rank -> pid of that rank
    local c
    for c in $(pgrep -P "$1"); do
        if tr '\0' '\n' < /proc/"$c"/environ 2>/dev/null | grep -qx "OMPI_COMM_WORLD_RANK=$2"; then echo "$c"; return; fi
    done
}

wait_for_pngs() {  # dir count timeout-seconds
    local t=0
    while [ "$(ls "$1" 2>/dev/null | grep -c '^frame_.*\.png$')" -lt "$2" ]; do
        sleep 0.1; t=$((t + 1)); [ $t -lt $(($3 * 10)) ] || fail "fewer than $2 frames in $1 after $3 s"
    done
}

wait_for_line() {  # file text timeout-seconds
    local t=0
    until grep -q "$2" "$1" 2> /dev/null; do
        sleep 0.1; t=$((t + 1)); [ $t -lt $(($3 * 10)) ] || { cat "$1"; fail "no \"$2\" in $1 after $3 s"; }
    done
}

wait_for_video() {  # file timeout-seconds: until the file plays at least one frame
    local t=0
    while [ "$(probe "$1" 2>/dev/null | awk '{print $1 + 0}')" -lt 1 ]; do
        sleep 0.2; t=$((t + 2)); [ $t -lt $(($2 * 10)) ] || fail "$1 plays no frame after $2 s"
    done
}

case "$CASE" in
modes)
    scene=$1; shift
    ref=""
    # The scene goes out in 4 KiB broadcast pieces (as one beyond 2 GiB goes out in 1 GiB ones).
    export RAYFARM_BROADCAST_CHUNK=4093
    for np in 1 2 3; do
        for mode in pixel frame; do
            out=m_${np}_$mode
            rm -rf "$out.mp4" "$out.mp4.frames"
            mpi "$np" render "$scene" -o "$out.mp4" --mode "$mode" --stats "$out.json" "$@" 2> "$out.log" ||
                { cat "$out.log"; fail "np $np $mode: rayfarm failed"; }
            pngs_md5 "$out.mp4.frames" > "$out.md5"
            n=$(wc -l < "$out.md5")
            [ "$n" -ge 1 ] || fail "np $np $mode: no PNG frames"
            if [ -z "$ref" ]; then ref=$out; else
                cmp -s "$ref.md5" "$out.md5" || { diff "$ref.md5" "$out.md5" | head; fail "np $np $mode: PNGs differ from $ref"; }
            fi
            read -r frames w h rate < <(probe "$out.mp4")
            first=$(ls "$out.mp4.frames" | grep -m1 '^frame_' | sed 's/frame_0*\([0-9]\)/\1/; s/\.png//')
            [ "$frames" = "$n" ] || fail "np $np $mode: MP4 has $frames frames, expected $n"
            read -r pw ph < <(python3 -c "import struct,sys; d=open(sys.argv[1],'rb').read(24); print(*struct.unpack('>II', d[16:24]))" "$out.mp4.frames/$(ls "$out.mp4.frames" | grep -m1 '^frame_')")
            [ "$w" = "$pw" ] && [ "$h" = "$ph" ] || fail "np $np $mode: MP4 is ${w}x$h, frames are ${pw}x$ph"
            want_rate=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['video_fps'])" "$out.json")
            python3 -c "import sys; n,d=map(int,sys.argv[1].split('/')); sys.exit(abs(n/d-float(sys.argv[2]))>1e-3)" "$rate" "$want_rate" ||
                fail "np $np $mode: MP4 rate $rate, timeline $want_rate"
            p=$(min_psnr "$out.mp4" "$out.mp4.frames" "$first")
            python3 -c "import sys; sys.exit(float(sys.argv[1]) < float(sys.argv[2]))" "$p" "$PSNR_MIN" ||
                fail "np $np $mode: a frame decodes at $p dB PSNR, below $PSNR_MIN"
            echo "np $np $mode: $n frames ${w}x$h at $rate, PNGs identical to $ref, min PSNR $p dB"
        done
    done
    # Frame mode renders each frame on one rank, so the film's rays are the same at every rank
    # count, the bounce cache's included: every rank builds that cache before its work begins
    # (a worker while rank 0 decides the job), not inside the run.
    for np in 2 3; do
        python3 - m_1_frame.json "m_${np}_frame.json" <<'PY' || fail "np $np frame: the film's rays differ from one process's"
import json, sys
a, b = (json.load(open(f))["rays"] for f in sys.argv[1:])
for k in sorted(set(a) | set(b)):
    if a.get(k) != b.get(k):
        print(f"rays {k}: {a.get(k)} in one process, {b.get(k)} in {sys.argv[2]}", file=sys.stderr)
        sys.exit(1)
PY
    done
    echo "frame mode: the film's rays (bounce cache $(python3 -c "import json; print(json.load(open('m_1_frame.json'))['rays'].get('bounce_cache'))")) the same at np 1, 2, 3"
    # Lossless: the decoded video is the PNGs, bit for bit.
    mpi 2 render "$scene" -o lossless.mp4 --no-frames --lossless "$@" 2> lossless.log || { cat lossless.log; fail "lossless run failed"; }
    video_md5 lossless.mp4 > lossless.vmd5
    pngs_rgb_md5 "$ref.mp4.frames" "$first" > ref.vmd5
    cmp -s lossless.vmd5 ref.vmd5 || fail "lossless MP4 does not decode to the PNG frames"
    echo "lossless: $(wc -l < ref.vmd5) decoded frames equal the PNGs"
    ;;
resume)
    args=(render "$FLIGHT" --size 64x48 --frames 0:11)
    rm -rf full.* part.* edited.*
    mpi 2 "${args[@]}" -o full.mp4 2> full.log || { cat full.log; fail "full run failed"; }
    mpi 2 "${args[@]}" -o part.mp4 2> part.log || { cat part.log; fail "second run failed"; }
    rm part.mp4 part.mp4.frames/frame_000003.png part.mp4.frames/frame_000007.png part.mp4.frames/frame_000008.png
    mpi 3 "${args[@]}" -o part.mp4 --resume 2> resume.log || { cat resume.log; fail "resume failed"; }
    grep -q "9 of 12 frames kept in part.mp4.frames, 3 to render" resume.log || { cat resume.log; fail "resume did not render exactly the 3 missing frames"; }
    cmp -s <(pngs_md5 full.mp4.frames) <(pngs_md5 part.mp4.frames) || fail "resumed PNGs differ"
    cmp -s <(video_md5 full.mp4) <(video_md5 part.mp4) || fail "resumed video decodes differently"
    # A different size must not resume from these frames.
    if mpi 2 "${args[@]}" -o part.mp4 --resume --size 32x24 2> wrong.log; then fail "resume with other settings accepted"; fi
    grep -q "rendered with other settings (width was 64, now 32, height was 48, now 24)" wrong.log || { cat wrong.log; fail "no clear message for mismatched resume"; }
    echo "resume: 3 frames re-rendered, video identical"
    # Issue 14 #9: a kept PNG with a corrupt middle (header and IEND intact) is rendered again.
    printf 'Z' | dd of=part.mp4.frames/frame_000005.png bs=1 seek=60 conv=notrunc status=none
    rm part.mp4
    mpi 2 "${args[@]}" -o part.mp4 --resume 2> corrupt.log || { cat corrupt.log; fail "resume over a corrupt frame failed"; }
    grep -q "frame_000005.png: does not match the checksum recorded when it was written; rendering it again" corrupt.log ||
        { cat corrupt.log; fail "corrupt kept frame not noticed"; }
    grep -q "11 of 12 frames kept in part.mp4.frames, 1 to render" corrupt.log || { cat corrupt.log; fail "corrupt frame not re-rendered"; }
    cmp -s <(video_md5 full.mp4) <(video_md5 part.mp4) || fail "video after re-rendering a corrupt frame differs"
    echo "resume: a corrupt kept frame was noticed by its checksum and rendered again; video identical"
    # Issue 14 #5: the same settings over an edited scene are refused, naming the file.
    python3 -c "import json,sys; d=json.load(open(sys.argv[1])); json.dump(d, open('edited.json','w'))" "$FLIGHT"
    mpi 2 render edited.json --size 64x48 --frames 0:3 -o edited.mp4 2> edited.log || { cat edited.log; fail "edited-scene run failed"; }
    python3 -c "import json; d=json.load(open('edited.json')); m=d['materials']; k=sorted(m)[0]; m[k]['color']=[0.1,0.9,0.1]; json.dump(d, open('edited.json','w'))"
    if mpi 2 render edited.json --size 64x48 --frames 0:3 -o edited.mp4 --resume 2> changed.log; then fail "resume over a changed scene accepted"; fi
    [ "$(grep -c 'rayfarm: error' changed.log)" = 1 ] && grep -q "the scene changed since its frames were rendered (edited.json changed)" changed.log ||
        { cat changed.log; fail "changed scene not refused in one line naming the file"; }
    echo "resume: a changed scene file is refused: $(grep 'rayfarm: error' changed.log | cut -c1-120)"
    ;;
resume-scene)
    # Any scene (e.g. a skinned model, posed per frame): a resumed run at another rank count
    # renders only the missing frames, and they equal those of a whole run byte for byte.
    scene=$1; shift
    args=(render "$scene" "$@")
    rm -rf full.* part.*
    mpi 2 "${args[@]}" -o full.mp4 --mode frame 2> full.log || { cat full.log; fail "full run failed"; }
    n=$(ls full.mp4.frames | grep -c '^frame_.*\.png$')
    [ "$n" -ge 4 ] || fail "only $n frames"
    mpi 1 "${args[@]}" -o part.mp4 2> part.log || { cat part.log; fail "second run failed"; }
    rm part.mp4
    gone=$(ls part.mp4.frames | grep '^frame_.*\.png$' | sed -n '2p;4p')
    for f in $gone; do rm "part.mp4.frames/$f"; done
    mpi 3 "${args[@]}" -o part.mp4 --resume --mode pixel 2> resume.log || { cat resume.log; fail "resume failed"; }
    grep -q "$((n - 2)) of $n frames kept in part.mp4.frames, 2 to render" resume.log || { cat resume.log; fail "resume did not render exactly the 2 missing frames"; }
    cmp -s <(pngs_md5 full.mp4.frames) <(pngs_md5 part.mp4.frames) || fail "resumed PNGs differ"
    cmp -s <(video_md5 full.mp4) <(video_md5 part.mp4) || fail "resumed video decodes differently"
    [ "$(pngs_md5 full.mp4.frames | awk '{print $1}' | sort -u | wc -l)" = "$n" ] || fail "some frames are identical: nothing moves"
    echo "resume-scene: $n frames, 2 re-rendered at np 3 pixel mode, identical to np 2 frame mode"
    ;;
interrupt)
    args=(render "$FLIGHT" --size 320x180 --spp 9)
    rm -rf int.* ref.*
    mpirun --oversubscribe -np 2 "$RAYFARM" "${args[@]}" -o int.mp4 2> int.log &
    pid=$!
    wait_for_pngs int.mp4.frames 3 60
    kill -INT "$pid"
    set +e; wait "$pid"; set -e
    grep -q "rayfarm: interrupted" int.log || { cat int.log; fail "no interrupt message"; }
    grep -q -- "--resume" int.log || { cat int.log; fail "no resume hint"; }
    # Issue 14 #9: the printed command keeps mpirun's own options, so it works as printed.
    grep -q "rayfarm: to resume: mpirun --oversubscribe -np 2 " int.log || { cat int.log; fail "resume command drops mpirun's options"; }
    read -r frames w h rate < <(probe int.mp4)
    kept=$(ls int.mp4.frames | grep -c '^frame_.*\.png$')
    [ "$frames" -ge 1 ] && [ "$frames" -lt 97 ] || fail "partial MP4 has $frames frames"
    [ "$frames" -le "$kept" ] || fail "MP4 has $frames frames but only $kept PNGs were kept"
    echo "interrupt: partial MP4 plays $frames frames ($kept PNGs kept)"
    mpi 2 "${args[@]}" -o int.mp4 --resume 2> resume.log || { cat resume.log; fail "resume after interrupt failed"; }
    read -r frames w h rate < <(probe int.mp4)
    [ "$frames" = 97 ] || fail "resumed MP4 has $frames frames"
    "$RAYFARM" "${args[@]}" -o ref.mp4 2> ref.log || fail "reference run failed"
    cmp -s <(pngs_md5 int.mp4.frames) <(pngs_md5 ref.mp4.frames) || fail "interrupted+resumed PNGs differ from one uninterrupted run"
    cmp -s <(video_md5 int.mp4) <(video_md5 ref.mp4) || fail "interrupted+resumed video differs from one uninterrupted run"
    echo "interrupt: resumed video identical to an uninterrupted run"
    ;;
interrupt-slow)
    # Issue 14 #3: SIGTERM while a slow encoder is behind (--preset slow looks 50 frames ahead):
    # the interrupted line and the resume command still go out before mpirun's SIGKILL, and the
    # file plays what it held.
    rm -rf slow.*
    mpirun --oversubscribe -np 2 "$RAYFARM" render "$FLIGHT" --size 320x180 --spp 4 --preset slow -o slow.mp4 2> slow.log &
    pid=$!
    wait_for_pngs slow.mp4.frames 20 60
    kill -TERM "$pid"
    set +e; wait "$pid"; set -e
    grep -q "^rayfarm: interrupted (SIGTERM): the video slow.mp4 holds .* (playable)$" slow.log || { cat slow.log; fail "no interrupted line"; }
    grep -A1 "rayfarm: interrupted" slow.log | grep -q "^rayfarm: to resume: mpirun .*--resume$" || { cat slow.log; fail "no resume command"; }
    read -r frames w h rate < <(probe slow.mp4)
    [ -n "$frames" ] && [ "$frames" -ge 1 ] || fail "slow.mp4 does not play after SIGTERM"
    said=$(sed -n 's/^rayfarm: interrupted (SIGTERM): the video slow.mp4 holds frames 0–\([0-9]*\) .*/\1/p; s/^rayfarm: interrupted (SIGTERM): the video slow.mp4 holds frame 0 .*/0/p' slow.log)
    [ -n "$said" ] && [ "$frames" -ge $((said + 1)) ] || fail "the line said frames 0–$said, the file plays $frames"
    echo "interrupt-slow: $(grep 'rayfarm: interrupted' slow.log | cut -d: -f3-); it plays $frames frames"
    ;;
killed-master)
    # Issue 14 #3: kill -9 of rank 0 itself mid-film (nothing of rayfarm runs after it): the file
    # plays the frames finished (written one fragment per frame), holding the packets an
    # uninterrupted run holds for them, and --resume gives the file an uninterrupted run gives.
    # EXT: mp4 (lossless, so every decoded frame is checked against its PNG) or mov (ProRes 4444).
    ext=$1
    lossless=()
    [ "$ext" = mp4 ] && lossless=(--lossless)
    args=(render "$FLIGHT" --size 160x90 --spp 9 --frames 0:47 "${lossless[@]}")
    rm -rf k9.* ref9.*
    "$RAYFARM" "${args[@]}" -o ref9.$ext 2> ref9.log || { cat ref9.log; fail "uninterrupted run failed"; }
    mpirun --oversubscribe -np 2 "$RAYFARM" "${args[@]}" -o k9.$ext 2> k9.log &
    pid=$!
    wait_for_pngs k9.$ext.frames 8 60
    # Frames reach the video a chunk at a time, encoded where they were rendered: eight PNGs can
    # be on disk before rank 0 has joined the first chunk (about one run in three here), and a
    # kill then leaves a file with no frame to play. The kill comes once the file plays one.
    wait_for_video k9.$ext 60
    master=$(rank_pid "$pid" 0)
    [ -n "$master" ] || fail "rank 0 not found"
    start=$(date +%s.%N)
    kill -9 "$master"
    set +e; wait "$pid"; rc=$?; set -e
    took=$(python3 -c "import sys,time; print(round(time.time()-float(sys.argv[1]),2))" "$start")
    [ "$rc" -ne 0 ] || fail "a run whose rank 0 was killed exited 0"
    kept=$(ls k9.$ext.frames | grep -c '^frame_.*\.png$')
    # Frames 0..prefix-1 all have their PNG: the video can hold at most those.
    prefix=0
    while [ -e "k9.$ext.frames/$(printf 'frame_%06d.png' $prefix)" ]; do prefix=$((prefix + 1)); done
    read -r frames w h rate < <(probe k9.$ext)
    [ -n "$frames" ] && [ "$frames" -ge 1 ] || { cat k9.log; fail "after kill -9 of rank 0 the $ext does not play"; }
    [ "$frames" -le "$prefix" ] || fail "the $ext plays $frames frames, but only frames 0-$((prefix - 1)) were finished"
    read -r _ rw rh rrate < <(probe ref9.$ext)
    [ "$w $h $rate" = "$rw $rh $rrate" ] || fail "the partial $ext is ${w}x$h at $rate, the uninterrupted one ${rw}x$rh at $rrate"
    # Not re-encoded at the end: its packets are the uninterrupted run's first packets, bit for bit.
    packets() { ffmpeg -v error -i "$1" -map 0:v -c copy -f framemd5 - | grep -v '^#' | awk -F, '{print $NF}'; }
    cmp -s <(packets k9.$ext) <(packets ref9.$ext | head -n "$frames") ||
        fail "the partial $ext's packets are not the first $frames of an uninterrupted run"
    if [ "$ext" = mp4 ]; then
        cmp -s <(video_md5 k9.$ext) <(pngs_rgb_md5 k9.$ext.frames 0 | head -n "$frames") ||
            fail "the partial MP4's frames do not decode to their PNGs"
    fi
    [ ! -e k9.$ext.remux ] || fail "a remux file was left although the film never completed"
    echo "killed-master ($ext): mpirun ended $took s after kill -9 of rank 0; the $ext plays $frames frames ($prefix finished in order, $kept PNGs)"
    mpi 2 "${args[@]}" -o k9.$ext --resume 2> resume9.log || { cat resume9.log; fail "resume after kill -9 of rank 0 failed"; }
    grep -q "frames kept in k9.$ext.frames" resume9.log || { cat resume9.log; fail "resume kept no frames"; }
    read -r frames w h rate < <(probe k9.$ext)
    [ "$frames" = 48 ] || fail "resumed $ext has $frames frames"
    # Complete: faststart (moov before mdat) and no fragments left.
    python3 - k9.$ext <<'PY' || fail "the resumed $ext is not one faststart moov"
import struct, sys
d = open(sys.argv[1], "rb").read()
boxes, i = [], 0
while i + 8 <= len(d):
    size, kind = struct.unpack(">I4s", d[i:i + 8])
    if size == 1: size = struct.unpack(">Q", d[i + 8:i + 16])[0]
    boxes.append(kind.decode("latin1")); i += size if size else len(d)
sys.exit(not (boxes.index("moov") < boxes.index("mdat") and "moof" not in boxes))
PY
    cmp -s k9.$ext ref9.$ext || fail "killed+resumed $ext differs from one uninterrupted run"
    echo "killed-master ($ext): resumed to a faststart file byte-identical to an uninterrupted run"
    ;;
killed-worker)
    rm -rf kill.*
    mpirun --oversubscribe -np 2 "$RAYFARM" render "$FLIGHT" -o kill.mp4 --size 320x180 --spp 9 2> kill.log &
    pid=$!
    wait_for_pngs kill.mp4.frames 2 60
    victim=$(rank_pid "$pid" 1)
    [ -n "$victim" ] || fail "rank 1 not found"
    start=$(date +%s.%N)
    kill -9 "$victim"
    set +e; wait "$pid"; rc=$?; set -e
    took=$(python3 -c "import sys,time; print(round(time.time()-float(sys.argv[1]),2))" "$start")
    [ "$rc" -ne 0 ] || fail "run with a killed worker exited 0"
    grep -Eq "rayfarm: error: rank 1 on [^ ]+ .*frame" kill.log || { cat kill.log; fail "no message naming rank 1 and its frame"; }
    python3 -c "import sys; sys.exit(float(sys.argv[1]) > 10)" "$took" || fail "took $took s to stop (bound 10 s)"
    read -r frames w h rate < <(probe kill.mp4)
    echo "killed-worker: stopped in $took s: $(grep 'rayfarm: error' kill.log); MP4 plays $frames frames"
    ;;
killed-worker-pixel)
    # Issue 32: pixel mode assembles each chunk on a rank. kill -9 of rank 1, which renders
    # tiles and assembles chunks, stops the run naming it; the video plays; --resume at another
    # rank count gives the file and PNGs of one process, byte for byte.
    rm -rf kp.* kpone.*
    small=(render "$FLIGHT" --size 160x90 --spp 9 --frames 0:23 --chunk-frames 6 --lossless)
    "$RAYFARM" "${small[@]}" -o kpone.mp4 2> kpone.log || { cat kpone.log; fail "one-process reference failed"; }
    mpirun --oversubscribe -np 3 "$RAYFARM" "${small[@]}" --mode pixel --timeout 3 -o kp.mp4 2> kp.log &
    pid=$!
    wait_for_pngs kp.mp4.frames 3 60
    victim=$(rank_pid "$pid" 1)
    rank0=$(rank_pid "$pid" 0)
    [ -n "$victim" ] && [ -n "$rank0" ] || fail "rank 0 or 1 not found"
    kill -9 "$victim"
    set +e; wait "$pid"; rc=$?; set -e
    [ "$rc" -ne 0 ] || fail "pixel run with a killed worker exited 0"
    # mpirun can return while rank 0 still leaves (it holds the output's lock until then).
    for _ in $(seq 100); do kill -0 "$rank0" 2> /dev/null || break; sleep 0.1; done
    ! kill -0 "$rank0" 2> /dev/null || fail "rank 0 still runs 10 s after mpirun returned"
    grep -q "each assembled from the tiles and encoded by one rank" kp.log || { cat kp.log; fail "pixel mode did not assemble chunks on the ranks"; }
    grep -Eq "rayfarm: error: rank 1 on [^ ]+ .*frame" kp.log || { cat kp.log; fail "no message naming rank 1 and its frame"; }
    read -r frames w h rate < <(probe kp.mp4)
    kept=$(find kp.mp4.frames -name 'frame_*.png' | wc -l)
    mpirun --oversubscribe -np 2 "$RAYFARM" "${small[@]}" --mode pixel -o kp.mp4 --resume 2> kpres.log || { cat kpres.log; fail "resume failed"; }
    cmp -s kpone.mp4 kp.mp4 || fail "resumed pixel run: the MP4 differs from one process's"
    cmp -s <(pngs_md5 kpone.mp4.frames) <(pngs_md5 kp.mp4.frames) || fail "resumed pixel run: PNGs differ from one process's"
    echo "killed-worker-pixel: $(grep -Eo 'rank 1 on [^ ]+ .{0,70}' kp.log | head -1); MP4 played $frames frames, $kept PNGs kept; resumed at np 2: byte-identical to one process"
    ;;
stalled-worker)
    # Issue 45 #3: rank 2 stopped (SIGSTOP) past --timeout is given up on and its frames go to
    # rank 1; continued (SIGCONT), it speaks again: what it sends is ignored and said so, it is
    # told to leave, and the film is the one a single process makes, byte for byte. Plain
    # mpirun: a stopped rank is no dead one, so no launcher option is needed.
    rm -rf stall.* stallone.*
    small=(render "$FLIGHT" --size 160x90 --spp 9 --frames 0:47 --chunk-frames 6)
    "$RAYFARM" "${small[@]}" -o stallone.mp4 2> stallone.log || { cat stallone.log; fail "one-process reference failed"; }
    mpirun --oversubscribe -np 3 "$RAYFARM" "${small[@]}" --mode frame -o stall.mp4 --timeout 4 2> stall.log &
    pid=$!
    wait_for_pngs stall.mp4.frames 4 60
    victim=$(rank_pid "$pid" 2)
    [ -n "$victim" ] || fail "rank 2 not found"
    kill -STOP "$victim"
    wait_for_line stall.log "stopped answering" 60
    kill -CONT "$victim"
    set +e; wait "$pid"; rc=$?; set -e
    [ "$rc" = 0 ] || { cat stall.log; fail "run with a worker stopped and continued exited $rc"; }
    grep -Eq "rayfarm: warning: rank 2 on [^ ]+ stopped answering .*frame.*its work goes to the 1 rendering rank left" stall.log ||
        { cat stall.log; fail "no warning naming rank 2, its frame and where its work went"; }
    cmp -s stallone.mp4 stall.mp4 || { cat stall.log; fail "the MP4 differs from one process's"; }
    cmp -s <(pngs_md5 stallone.mp4.frames) <(pngs_md5 stall.mp4.frames) || fail "PNGs differ from one process's"
    late=$(grep -c "answered again" stall.log || true)
    echo "stalled-worker: $(grep -Eo 'rank 2 on [^ ]+ stopped answering .{0,60}' stall.log | head -1); late words noted: $late; MP4 and PNGs byte-identical to one process"
    ;;
suspend-all)
    # Issue 14 #4: the whole job paused (Slurm suspend, Ctrl-Z then fg) for longer than the
    # timeout is not a lost worker: every rank was stopped, rank 0 included.
    rm -rf susp.*
    mpirun --oversubscribe -np 3 "$RAYFARM" render "$FLIGHT" -o susp.mp4 --size 160x90 --spp 4 --frames 0:59 --timeout 2 2> susp.log &
    pid=$!
    wait_for_pngs susp.mp4.frames 2 60
    ranks=$(pgrep -P "$pid" | tr '\n' ' ')
    [ "$(wc -w <<<"$ranks")" = 3 ] || fail "expected 3 ranks under mpirun, found: $ranks"
    kill -STOP $ranks
    sleep 6
    kill -CONT $ranks
    set +e; wait "$pid"; rc=$?; set -e
    [ "$rc" = 0 ] || { cat susp.log; fail "a 6 s pause of every rank (timeout 2 s) ended the run with $rc"; }
    read -r frames w h rate < <(probe susp.mp4)
    [ "$frames" = 60 ] || fail "paused run's MP4 has $frames frames, expected 60"
    echo "suspend-all: every rank stopped for 6 s (timeout 2 s); the run finished all 60 frames"
    ;;
suspend-master)
    # Issue 14 #4: rank 0 alone stopped; the workers notice the silent master and leave with a
    # message, so mpirun ends the job instead of idling forever.
    rm -rf smaster.*
    mpirun --oversubscribe -np 3 "$RAYFARM" render "$FLIGHT" -o smaster.mp4 --size 160x90 --spp 4 --timeout 2 2> smaster.log &
    pid=$!
    wait_for_pngs smaster.mp4.frames 2 60
    master=$(rank_pid "$pid" 0)
    [ -n "$master" ] || fail "rank 0 not found"
    start=$(date +%s.%N)
    kill -STOP "$master"
    ( sleep 40; kill -CONT "$master" 2>/dev/null; kill "$pid" 2>/dev/null ) > /dev/null 2>&1 &  # not holding ctest's pipe open
    guard=$!
    set +e; wait "$pid"; rc=$?; set -e
    took=$(python3 -c "import sys,time; print(round(time.time()-float(sys.argv[1]),2))" "$start")
    kill "$guard" 2>/dev/null || true
    kill -CONT "$master" 2>/dev/null || true
    [ "$rc" -ne 0 ] || fail "a run whose master was stopped exited 0"
    grep -Eq "rayfarm: error: rank [12] on [^:]+: rank 0 has been silent" smaster.log ||
        { cat smaster.log; fail "no worker said that rank 0 fell silent"; }
    python3 -c "import sys; sys.exit(float(sys.argv[1]) > 15)" "$took" || fail "mpirun took $took s to end (bound: the 2 s --timeout + 13 s for mpirun to end the job)"
    echo "suspend-master: job ended $took s after rank 0 was stopped: $(grep -m1 'rank 0 has been silent' smaster.log)"
    ;;
signals)
    # Issue 14 #9: a plain process reports the signal it got, exits 128 + its number, and prints
    # the interrupted line and the resume command together.
    for sig in INT TERM; do
        rm -rf sig_$sig.*
        "$RAYFARM" render "$FLIGHT" -o sig_$sig.mp4 --size 320x180 --spp 9 2> sig_$sig.log &
        pid=$!
        wait_for_pngs sig_$sig.mp4.frames 1 60
        kill -$sig "$pid"
        set +e; wait "$pid"; rc=$?; set -e
        want=$([ $sig = INT ] && echo 130 || echo 143)
        [ "$rc" = "$want" ] || { cat sig_$sig.log; fail "SIG$sig: exit $rc, expected $want"; }
        grep -q "rayfarm: interrupted (SIG$sig)" sig_$sig.log || { cat sig_$sig.log; fail "SIG$sig not named"; }
        grep -A1 "rayfarm: interrupted" sig_$sig.log | grep -q "^rayfarm: to resume: .*--resume$" || { cat sig_$sig.log; fail "SIG$sig: no resume command after the interrupted line"; }
    done
    echo "signals: SIGINT exits 130, SIGTERM 143, each named, resume command printed"
    ;;
one-frame)
    for mode in pixel frame auto; do
        rm -rf one_$mode.*
        mpi 2 render "$SRC/tests/farm/data/still_small.json" -o one_$mode.mp4 --size 64x48 --mode $mode 2> one_$mode.log ||
            { cat one_$mode.log; fail "one-frame $mode failed"; }
        read -r frames w h rate < <(probe one_$mode.mp4)
        [ "$frames $w $h" = "1 64 48" ] || fail "one-frame $mode: got '$frames $w $h'"
    done
    grep -q "mode pixel (auto: 1 frame" one_auto.log || { cat one_auto.log; fail "auto did not pick pixel mode for one frame"; }
    cmp -s <(pngs_md5 one_pixel.mp4.frames) <(pngs_md5 one_frame.mp4.frames) || fail "one-frame PNGs differ between modes"
    echo "one-frame: 1-frame MP4 in every mode"
    ;;
odd-size)
    for np in 1 2; do
        rm -rf odd_$np.*
        mpi $np render "$FLIGHT" -o odd_$np.mp4 --size 321x241 --frames 0:2 --mode pixel 2> odd_$np.log ||
            { cat odd_$np.log; fail "321x241 failed"; }
    done
    grep -q "the video is 322x242" odd_1.log || { cat odd_1.log; fail "no note about padding"; }
    cmp -s <(pngs_md5 odd_1.mp4.frames) <(pngs_md5 odd_2.mp4.frames) || fail "321x241 PNGs differ between 1 and 2 ranks"
    read -r frames w h rate < <(probe odd_2.mp4)
    [ "$frames $w $h" = "3 322 242" ] || fail "321x241: MP4 is '$frames $w $h'"
    p=$(min_psnr odd_2.mp4 odd_2.mp4.frames 0 321:241)
    python3 -c "import sys; sys.exit(float(sys.argv[1]) < float(sys.argv[2]))" "$p" "$PSNR_MIN" || fail "321x241: PSNR $p below $PSNR_MIN"
    echo "odd-size: 321x241 frames, 322x242 video, min PSNR $p dB over the visible area"
    ;;
bad-output)
    start=$(date +%s.%N)
    # A missing folder is made (issue 47); one that cannot be made, a file in its way, is refused.
    : > not-a-dir
    set +e; mpi 2 render "$FLIGHT" -o not-a-dir/x.mp4 2> bad.log; rc=$?; set -e
    [ "$rc" -eq 2 ] || { cat bad.log; fail "unwritable -o: exit $rc, expected 2"; }
    [ "$(grep -c 'rayfarm: error' bad.log)" = 1 ] || { cat bad.log; fail "expected exactly one error line"; }
    grep -q "rayfarm: error: not-a-dir: cannot create the folder for not-a-dir/x.mp4" bad.log || { cat bad.log; fail "message does not name the folder"; }
    grep -q "frames 0" bad.log && fail "rendering was planned before the output check"
    set +e; "$RAYFARM" render "$FLIGHT" -o out.mp4 --mode sideways 2> bad2.log; rc=$?; set -e
    [ "$rc" -eq 2 ] && grep -q "rayfarm: error: --mode" bad2.log || { cat bad2.log; fail "bad --mode not refused"; }
    # A rate below what MP4's time base holds, refused before rendering rather than at the first write.
    set +e; mpi 2 render "$FLIGHT" -o slow.mp4 --fps 1e-9 2> bad3.log; rc=$?; set -e
    [ "$rc" -eq 2 ] && [ "$(grep -c 'rayfarm: error' bad3.log)" = 1 ] && grep -q "rayfarm: error: --fps: expected a rate from 0.001" bad3.log ||
        { cat bad3.log; fail "--fps 1e-9: exit $rc, expected 2 and one line"; }
    grep -q "frames 0" bad3.log && fail "--fps 1e-9: rendering was planned"
    set +e; mpi 2 render "$FLIGHT" -o fast.gif --fps 200 2> bad4.log; rc=$?; set -e
    [ "$rc" -eq 2 ] && [ "$(grep -c 'rayfarm: error' bad4.log)" = 1 ] && grep -q "rayfarm: error: fast.gif: a GIF's frame delays" bad4.log ||
        { cat bad4.log; fail "GIF at 200 fps: exit $rc, expected 2 and one line"; }
    echo "bad-output: refused at once with exit 2"
    ;;
full-disk)
    # The video's header fails to write (a full disk: -o links to /dev/full) after the scene went
    # to the workers and before the master's loop starts. Rank 0 must tell them to leave: it
    # used to wait in MPI_Finalize, with the error line unprinted, for workers waiting for work.
    [ -w /dev/full ] || { echo "full-disk: skipped (no writable /dev/full)"; exit 0; }
    ln -sf /dev/full full.mp4
    for np in 2 3; do
        start=$(date +%s.%N)
        set +e; timeout 60 mpirun --oversubscribe -np "$np" "$RAYFARM" render "$FLIGHT" -o full.mp4 --no-frames 2> full_$np.log; rc=$?; set -e
        secs=$(awk -v a="$start" -v b="$(date +%s.%N)" 'BEGIN { printf "%.1f", b - a }')
        [ "$rc" -ne 124 ] || { cat full_$np.log; fail "$np ranks: still running after 60 s (rank 0 waits for its workers)"; }
        [ "$rc" -eq 1 ] || { cat full_$np.log; fail "$np ranks: exit $rc, expected 1"; }
        [ "$(grep -c 'rayfarm: error' full_$np.log)" = 1 ] && grep -q "rayfarm: error: full.mp4: cannot write the mp4 header: No space left on device" full_$np.log ||
            { cat full_$np.log; fail "$np ranks: expected one error line naming full.mp4 and the full disk"; }
        echo "full-disk: $np ranks stop in $secs s with one error line"
    done
    ;;
lost-worker)
    # Issue 45 #1: under mpirun --enable-recovery, kill -9 of rank 2 of 4 in MODE (frame,
    # pixel) once AT frames are done (early, late): rank 0 names it, its frames, tiles and chunks
    # go to ranks 1 and 3, and the MP4 and PNGs are byte-identical to one process's; --stats
    # lists the lost worker. RANKS "1 3": two of four killed. --timeout 6: on a machine loaded
    # ten times over its cores (ctest -j2 beside builds) a live rank's heartbeat was once late by
    # 4 s, and two such false losses left no rank to render.
    mode=$1 at=$2 victims=${3:-2}
    name=lost_${mode}_$at
    rm -rf $name.* lostone.*
    # At 9 spp the film took about a second: in CI the 18 frames after the 30th (and once the 44
    # after the 4th, on a loaded machine) took less than finding and killing the rank, and the
    # film was done before the kill. At 64 spp it takes about 4 s here, so over a second of it
    # is left when the kill lands even late.
    spp=64
    small=(render "$FLIGHT" --size 160x90 --spp $spp --frames 0:47 --chunk-frames 6)
    "$RAYFARM" "${small[@]}" -o lostone.mp4 2> lostone.log || { cat lostone.log; fail "one-process reference failed"; }
    mpirun --oversubscribe --enable-recovery -np 4 "$RAYFARM" "${small[@]}" --mode "$mode" --timeout 6 --stats $name.json \
        -o $name.mp4 2> $name.log &
    pid=$!
    wait_for_pngs $name.mp4.frames "$at" 60
    pids=""
    for r in $victims; do v=$(rank_pid "$pid" "$r"); [ -n "$v" ] || fail "rank $r not found"; pids="$pids $v"; done
    kill -9 $pids
    set +e; wait "$pid"; rc=$?; set -e
    [ "$rc" = 0 ] || { cat $name.log; fail "exit $rc"; }
    grep -q "^rayfarm: wrote $name.mp4: 48 frames" $name.log || { cat $name.log; fail "the film did not complete"; }
    for r in $victims; do
        grep -Eq "rayfarm: warning: rank $r on [^ ]+ stopped answering .*its work goes to the" $name.log ||
            { cat $name.log; fail "no warning naming rank $r"; }
    done
    cmp -s lostone.mp4 $name.mp4 || fail "the MP4 differs from one process's"
    cmp -s <(pngs_md5 lostone.mp4.frames) <(pngs_md5 $name.mp4.frames) || fail "PNGs differ from one process's"
    python3 - "$name.json" $victims <<'PY' || fail "--stats does not list the lost workers"
import json, sys
lost = json.load(open(sys.argv[1])).get("lost_workers", [])
# The killed ranks; on a loaded machine another may have been silent past --timeout too (its
# work then went elsewhere as well, and the film is still checked byte for byte above).
assert {int(r) for r in sys.argv[2:]} <= {l["rank"] for l in lost}, lost
assert all(l["at_s"] > 0 and l["requeued"] and l["doing"] for l in lost), lost
PY
    echo "lost-worker ($mode, killed at $at frames, ranks $victims): $(grep -c 'warning: rank' $name.log) lost, film byte-identical to one process; $(grep -m1 -Eo 'its work goes to .*' $name.log)"
    ;;
lost-encoder)
    # Issue 45 #1: kill -9 of a worker in the middle of encoding a chunk, in MODE (frame: the
    # rank renders the chunk's frames; pixel: it assembles them from every rank's tiles). The
    # test hook RAYFARM_TEST_STOP_ENCODING=9:FILE stops (SIGSTOP) the first worker whose encoder
    # has taken frame 9, the fourth of chunk 1 (frames 6-11), and writes its pid to FILE; it is
    # killed there. Rank 0 names it, chunk 1 opens again on another rank, and the film completes:
    # the MP4 byte-identical to one process's (its decoded frames too, framemd5) and the PNGs,
    # so nothing of the dead rank's half-encoded chunk reaches the video.
    mode=$1
    name=lenc_$mode
    rm -rf $name.* lencone.*
    small=(render "$FLIGHT" --size 160x90 --spp 9 --frames 0:47 --chunk-frames 6)
    "$RAYFARM" "${small[@]}" -o lencone.mp4 2> lencone.log || { cat lencone.log; fail "one-process reference failed"; }
    RAYFARM_TEST_STOP_ENCODING=9:$PWD/$name.stopped mpirun -x RAYFARM_TEST_STOP_ENCODING --oversubscribe --enable-recovery -np 4 \
        "$RAYFARM" "${small[@]}" --mode "$mode" --timeout 6 --stats $name.json -o $name.mp4 2> $name.log &
    pid=$!
    ( sleep 120; kill -9 "$pid" $(pgrep -P "$pid") 2> /dev/null ) > /dev/null 2>&1 &  # not holding ctest's pipe open
    guard=$!
    for _ in $(seq 600); do grep -qx '[0-9][0-9]*' $name.stopped 2> /dev/null && break; sleep 0.1; done
    grep -qx '[0-9][0-9]*' $name.stopped 2> /dev/null || { cat $name.log; fail "no worker stopped at the hook within 60 s"; }
    victim=$(cat $name.stopped)
    # Stopped at the hook (state T), one of this run's ranks, and not rank 0.
    for _ in $(seq 50); do [ "$(awk '{print $3}' /proc/"$victim"/stat 2> /dev/null)" = T ] && break; sleep 0.1; done
    [ "$(awk '{print $3}' /proc/"$victim"/stat 2> /dev/null)" = T ] || fail "pid $victim did not stop at the hook"
    rank=$(tr '\0' '\n' < /proc/"$victim"/environ | sed -n 's/^OMPI_COMM_WORLD_RANK=//p')
    [ -n "$rank" ] && [ "$rank" != 0 ] || fail "pid $victim is not a worker of this run (rank '$rank')"
    kill -9 "$victim"
    set +e; wait "$pid"; rc=$?; set -e
    kill "$guard" 2> /dev/null || true
    [ "$rc" = 0 ] || { cat $name.log; fail "exit $rc"; }
    grep -q "^rayfarm: wrote $name.mp4: 48 frames" $name.log || { cat $name.log; fail "the film did not complete"; }
    grep -Eq "rayfarm: warning: rank $rank on [^ ]+ stopped answering .*its work goes to the 2 rendering ranks left: (.*; )?chunk 1 \(frames 6.11\)" $name.log ||
        { cat $name.log; fail "no warning naming rank $rank and chunk 1 opened again"; }
    [ "$(probe $name.mp4 | awk '{print $1}')" = 48 ] || fail "the MP4 does not play 48 frames"
    cmp -s <(video_md5 lencone.mp4) <(video_md5 $name.mp4) || fail "the MP4's decoded frames differ from one process's"
    cmp -s lencone.mp4 $name.mp4 || fail "the MP4 differs from one process's"
    cmp -s <(pngs_md5 lencone.mp4.frames) <(pngs_md5 $name.mp4.frames) || fail "PNGs differ from one process's"
    echo "lost-encoder ($mode): rank $rank killed with frame 9 of chunk 1 (frames 6-11) in its encoder; $(grep -m1 -Eo 'its work goes to .*' $name.log); film byte-identical to one process (file, decoded frames, PNGs)"
    ;;
lost-all)
    # Issue 45 #2: every worker killed: no rendering rank is left, the run says so with the
    # resume command, no rank is left running, and --resume completes the film byte for byte.
    # (Open MPI 4.1.4's mpirun --enable-recovery exits 0 whatever its ranks' status: the
    # message is what tells.)
    rm -rf lall.* lallone.*
    small=(render "$FLIGHT" --size 160x90 --spp 9 --frames 0:47 --chunk-frames 6 --mode frame)
    "$RAYFARM" "${small[@]}" -o lallone.mp4 2> lallone.log || { cat lallone.log; fail "one-process reference failed"; }
    mpirun --oversubscribe --enable-recovery -np 4 "$RAYFARM" "${small[@]}" --timeout 2 -o lall.mp4 2> lall.log &
    pid=$!
    wait_for_pngs lall.mp4.frames 6 60
    rank0=$(rank_pid "$pid" 0)
    kill -9 $(rank_pid "$pid" 1) $(rank_pid "$pid" 2) $(rank_pid "$pid" 3)
    set +e; wait "$pid"; set -e
    grep -q "no worker is left to render" lall.log || { cat lall.log; fail "no line saying no worker is left"; }
    grep -q "to resume: .*--enable-recovery.*--resume$" lall.log || { cat lall.log; fail "no resume command"; }
    for _ in $(seq 100); do kill -0 "$rank0" 2> /dev/null || break; sleep 0.1; done
    ! kill -0 "$rank0" 2> /dev/null || fail "rank 0 still runs 10 s after mpirun returned"
    mpirun --oversubscribe --enable-recovery -np 4 "$RAYFARM" "${small[@]}" --timeout 2 -o lall.mp4 --resume 2> lallres.log ||
        { cat lallres.log; fail "resume failed"; }
    cmp -s lallone.mp4 lall.mp4 || fail "resumed: the MP4 differs from one process's"
    echo "lost-all: $(grep -Eo 'no worker is left to render' lall.log); resumed byte-identical to one process"
    ;;
lost-master)
    # Issue 45 #2: kill -9 of rank 0 under --enable-recovery (which keeps the job alive): every
    # worker sees rank 0's process end (the same machine: master_watch.h) and leaves by itself,
    # so no rank process is left --timeout + 2 s after the kill (a worker that cannot see rank
    # 0 waits for twice --timeout of silence: render_film.cpp says why), and --resume completes
    # the film byte for byte (MP4 and PNGs) as one clean process makes it.
    timeout=4
    rm -rf lmaster.* lmasterone.*
    small=(render "$FLIGHT" --size 160x90 --spp 9 --frames 0:47 --chunk-frames 6 --mode frame)
    "$RAYFARM" "${small[@]}" -o lmasterone.mp4 2> lmasterone.log || { cat lmasterone.log; fail "one-process reference failed"; }
    mpirun --oversubscribe --enable-recovery -np 4 "$RAYFARM" "${small[@]}" --timeout $timeout -o lmaster.mp4 2> lmaster.log &
    pid=$!
    wait_for_pngs lmaster.mp4.frames 6 60
    ranks=""
    for r in 0 1 2 3; do ranks="$ranks $(rank_pid "$pid" $r)"; done
    [ "$(wc -w <<<"$ranks")" = 4 ] || fail "expected 4 ranks, found:$ranks"
    start=$(date +%s.%N)
    kill -9 $(rank_pid "$pid" 0)
    ( sleep 60; kill -9 $ranks "$pid" 2> /dev/null ) > /dev/null 2>&1 &  # not holding ctest's pipe open
    guard=$!
    # Every rank's exit, as it happens (not mpirun's: it may return later).
    left=$ranks
    while [ -n "$left" ]; do
        still=""; for p in $left; do kill -0 "$p" 2> /dev/null && still="$still $p"; done; left=$still
        [ -z "$left" ] && break
        python3 -c "import sys,time; sys.exit(time.time()-float(sys.argv[1]) > float(sys.argv[2]))" "$start" $((timeout + 2)) || break
        sleep 0.05
    done
    took=$(python3 -c "import sys,time; print(round(time.time()-float(sys.argv[1]),2))" "$start")
    [ -z "$left" ] || { kill -9 $left 2> /dev/null; cat lmaster.log; fail "ranks$left still run $took s after rank 0 was killed (--timeout $timeout)"; }
    set +e; wait "$pid"; set -e
    kill "$guard" 2> /dev/null || true
    [ "$(grep -c "rank 0's process has ended (killed or crashed); this worker stops" lmaster.log)" = 3 ] ||
        { cat lmaster.log; fail "not every worker said rank 0's process ended"; }
    mpirun --oversubscribe --enable-recovery -np 4 "$RAYFARM" "${small[@]}" --timeout $timeout -o lmaster.mp4 --resume 2> lmasterres.log ||
        { cat lmasterres.log; fail "resume failed"; }
    grep -q "^rayfarm: wrote lmaster.mp4: 48 frames" lmasterres.log || { cat lmasterres.log; fail "the resumed film did not complete"; }
    cmp -s lmasterone.mp4 lmaster.mp4 || fail "resumed: the MP4 differs from one process's"
    cmp -s <(pngs_md5 lmasterone.mp4.frames) <(pngs_md5 lmaster.mp4.frames) || fail "resumed: PNGs differ from one process's"
    echo "lost-master: the last rank left $took s after kill -9 of rank 0 (--timeout $timeout); resumed byte-identical to one process (MP4 and PNGs)"
    ;;
lost-master-load)
    # Issue 45 #2: rank 0 dies before a broadcast of the scene: a test hook
    # (RAYFARM_TEST_MASTER_HOLD=files: before the scene's files go out, the workers wait for
    # them; =job: before the job goes out, the workers have built the scene) holds rank 0 there,
    # beating as while it loads a huge model. The workers wait past every silence limit (rank 0
    # may load for minutes); kill -9 of rank 0 then ends every rank within --timeout + 2 s; and
    # --resume (its scene broadcast in 4 KiB pieces) completes the film byte for byte (before
    # the job rank 0 has no frame list yet: --resume says so, and the run without it does).
    stage=$1 np=$2 timeout=2
    rm -rf hold.* holdone.*
    small=(render "$FLIGHT" --size 160x90 --spp 4 --frames 0:23 --chunk-frames 6 --mode frame)
    "$RAYFARM" "${small[@]}" -o holdone.mp4 2> holdone.log || { cat holdone.log; fail "one-process reference failed"; }
    RAYFARM_TEST_MASTER_HOLD=$stage mpirun -x RAYFARM_TEST_MASTER_HOLD --oversubscribe --enable-recovery -np "$np" "$RAYFARM" \
        "${small[@]}" --timeout $timeout -o hold.mp4 2> hold.log &
    pid=$!
    wait_for_line hold.log "rank 0 holds before broadcasting the $stage" 60
    ranks=""
    for r in $(seq 0 $((np - 1))); do ranks="$ranks $(rank_pid "$pid" "$r")"; done
    [ "$(wc -w <<<"$ranks")" = "$np" ] || fail "expected $np ranks, found:$ranks"
    ( sleep 60; kill -9 $ranks "$pid" 2> /dev/null ) > /dev/null 2>&1 &  # not holding ctest's pipe open
    guard=$!
    # Past the silence limit (twice --timeout, 4 s at least): rank 0's beats keep them waiting.
    sleep 6
    for p in $ranks; do kill -0 "$p" 2> /dev/null || { cat hold.log; fail "rank pid $p left while rank 0 loaded (and beat)"; }; done
    start=$(date +%s.%N)
    kill -9 $(rank_pid "$pid" 0)
    left=$ranks
    while [ -n "$left" ]; do
        still=""; for p in $left; do kill -0 "$p" 2> /dev/null && still="$still $p"; done; left=$still
        [ -z "$left" ] && break
        python3 -c "import sys,time; sys.exit(time.time()-float(sys.argv[1]) > float(sys.argv[2]))" "$start" $((timeout + 2)) || break
        sleep 0.05
    done
    took=$(python3 -c "import sys,time; print(round(time.time()-float(sys.argv[1]),2))" "$start")
    [ -z "$left" ] || { kill -9 $left 2> /dev/null; cat hold.log; fail "ranks$left still run $took s after rank 0 was killed before the $stage broadcast"; }
    set +e; wait "$pid"; set -e
    kill "$guard" 2> /dev/null || true
    [ "$(grep -c "rank 0's process has ended (killed or crashed); this worker stops" hold.log)" = $((np - 1)) ] ||
        { cat hold.log; fail "not every worker said rank 0's process ended"; }
    again=(--resume)
    if [ "$stage" = files ]; then
        # Killed before it decided the job, rank 0 wrote no frame list: --resume says so, and the
        # run without it takes over the dead run's locks.
        # (mpirun --enable-recovery exits 0 whatever its ranks' status: the line tells.)
        mpirun --oversubscribe --enable-recovery -np "$np" "$RAYFARM" "${small[@]}" --timeout $timeout -o hold.mp4 --resume 2> holdres.log || true
        grep -q "rayfarm: error: hold.mp4.frames: nothing to resume (no rayfarm-frames.json here; run without --resume)" holdres.log ||
            { cat holdres.log; fail "--resume after a rank 0 killed before the job: expected 'nothing to resume'"; }
        again=()
    fi
    RAYFARM_BROADCAST_CHUNK=4096 mpirun -x RAYFARM_BROADCAST_CHUNK --oversubscribe --enable-recovery -np "$np" "$RAYFARM" \
        "${small[@]}" --timeout $timeout -o hold.mp4 "${again[@]}" 2> holdres.log || { cat holdres.log; fail "the run after failed"; }
    grep -q "^rayfarm: wrote hold.mp4: 24 frames" holdres.log || { cat holdres.log; fail "the resumed film did not complete"; }
    cmp -s holdone.mp4 hold.mp4 || fail "resumed: the MP4 differs from one process's"
    cmp -s <(pngs_md5 holdone.mp4.frames) <(pngs_md5 hold.mp4.frames) || fail "resumed: PNGs differ from one process's"
    echo "lost-master-load: rank 0 held before the $stage broadcast 6 s, $((np - 1)) workers waited; the last rank left $took s after its kill -9 (--timeout $timeout); run again ${again[*]:-without --resume}: byte-identical (MP4 and PNGs)"
    ;;
poison-frame)
    # Issue 45 #2: a frame that kills every worker rendering it (the test hook
    # RAYFARM_TEST_CRASH_FRAME: SIGKILL once the worker renders it) stops the run after
    # --max-frame-failures K ranks were lost on it, naming the frame, with the resume command.
    rm -rf poison.*
    set +e
    RAYFARM_TEST_CRASH_FRAME=20 timeout 120 mpirun -x RAYFARM_TEST_CRASH_FRAME --oversubscribe --enable-recovery -np 4 "$RAYFARM" \
        render "$FLIGHT" --size 160x90 --spp 9 --frames 0:47 --chunk-frames 6 --mode frame --timeout 2 --max-frame-failures 2 \
        -o poison.mp4 2> poison.log
    rc=$?
    set -e
    [ "$rc" != 124 ] || { cat poison.log; fail "still running after 120 s"; }
    grep -q "rayfarm: error: .*frame 20 was being rendered by each of the 2 ranks lost so far holding it" poison.log ||
        { cat poison.log; fail "no error naming frame 20 and the 2 ranks"; }
    [ "$(grep -c 'stopped answering' poison.log)" -ge 2 ] || { cat poison.log; fail "expected 2 ranks lost before the stop"; }
    grep -q "to resume: .*--resume$" poison.log || { cat poison.log; fail "no resume command"; }
    echo "poison-frame: $(grep -Eo 'frame 20 was being rendered .{0,40}' poison.log)"
    ;;
*)
    fail "unknown case $CASE"
    ;;
esac
