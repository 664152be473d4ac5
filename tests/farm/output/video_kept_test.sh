#!/usr/bin/env bash
# Issue 46 #4 and #5: what the video holds when the run is cut short, checked on real processes
# and real files, every video decoded back with ffprobe/ffmpeg.
#   kill9       kill -9 at several moments of a film: the video always opens and plays exactly
#               the frames of an uninterrupted run's start (never "moov atom not found"), up to
#               what the frames folder holds
#   resume      a --resume killed with kill -9 midway leaves the earlier video byte for byte;
#               the same over a partial video: the playable frames never drop while it runs
#   mpi-2sigint two SIGINTs to `mpirun -np 3`: the interrupted line and the resume command
#               still reach mpirun's stderr, no lock is left, the video plays what the line
#               says; a --resume started the moment mpirun returns is not refused
# Usage: video_kept_test.sh RAYFARM SOURCE_DIR WORK_DIR CASE
set -euo pipefail
RAYFARM=$1 SRC=$2 WORK=$3 CASE=$4
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1 HWLOC_COMPONENTS=-gl
SCENE=$SRC/scenes/flight.json
rm -rf "$WORK"
mkdir -p "$WORK"
cd "$WORK"

fail() { echo "FAIL: $*" >&2; exit 1; }
# Frames a video plays: 0 for a file that opens with none; "unplayable" if ffprobe cannot open it.
frames_of() {
    local n
    n=$(ffprobe -v error -select_streams v:0 -count_frames -show_entries stream=nb_read_frames -of csv=p=0 "$1" 2> probe.err) ||
        { echo unplayable; return; }
    [ -n "$n" ] && [ "$n" != "N/A" ] || n=0
    echo "$n"
}
decoded() { ffmpeg -v error -i "$1" -f framemd5 -pix_fmt rgba - | grep -v '^#' | awk -F, '{print $NF}'; }
pngs() { ls "$1" 2>/dev/null | grep -c '^frame_.*\.png$' || true; }
wait_for_pngs() {  # dir count timeout-seconds
    local t=0
    while [ "$(pngs "$1")" -lt "$2" ]; do
        sleep 0.05; t=$((t + 1)); [ $t -lt $(($3 * 20)) ] || fail "fewer than $2 frames in $1 after $3 s"
    done
}
# 60 frames in chunks of 8, about 10 s on two cores.
film=(render "$SCENE" --size 128x72 --spp 64 --frames 0:59)

case "$CASE" in
kill9)
    "$RAYFARM" "${film[@]}" -o ref.mp4 --no-frames 2> ref.log || { cat ref.log; fail "reference run failed"; }
    decoded ref.mp4 > ref.md5
    [ "$(wc -l < ref.md5)" = 60 ] || fail "the reference plays $(wc -l < ref.md5) frames"
    summary=""
    # Killed after the first frame (no chunk joined yet), inside the first chunks, and later.
    for after in 1 5 10 20 35; do
        rm -rf k.mp4 k.mp4.*
        "$RAYFARM" "${film[@]}" -o k.mp4 2> k.log &
        a=$!
        wait_for_pngs k.mp4.frames "$after" 60
        kill -9 "$a"
        set +e; wait "$a"; set -e
        kept=$(pngs k.mp4.frames)
        n=$(frames_of k.mp4)
        [ "$n" != unplayable ] || fail "kill -9 after $after frames: k.mp4 ($(stat -c %s k.mp4) bytes) does not open: $(cat probe.err)"
        [ "$n" -le "$kept" ] || fail "kill -9 after $after frames: the video plays $n frames, the frames folder holds $kept"
        if [ "$after" -ge 20 ]; then
            # 20 frames rendered: chunks 0 and 1 (16 frames) were joined.
            [ "$n" -ge 16 ] || fail "kill -9 after $after frames: the video plays only $n frames"
        fi
        # Every frame it plays is the uninterrupted run's, in order, and decodes without error
        # (ffmpeg calls a file with no frame an error: that one opened, which is what is asked).
        summary="$summary ${after}:${n}/${kept}"
        [ "$n" -gt 0 ] || continue
        decoded k.mp4 > k.md5 2> dec.err || true
        [ ! -s dec.err ] || { cat dec.err; fail "kill -9 after $after frames: decoding errors"; }
        cmp -s k.md5 <(head -n "$n" ref.md5) || fail "kill -9 after $after frames: its $n frames are not the film's first $n"
    done
    echo "kill9: kill -9 after N PNGs, video frames/PNGs kept:$summary; each opens and matches the uninterrupted run"
    ;;
resume)
    "$RAYFARM" "${film[@]}" -o r.mp4 2> a.log || { cat a.log; fail "first run failed"; }
    cp r.mp4 whole.mp4
    # Frames 20-59 lost: the resume renders them again and rewrites the whole video.
    for f in $(seq 20 59); do rm r.mp4.frames/frame_0000$(printf %02d "$f").png; done
    "$RAYFARM" "${film[@]}" -o r.mp4 --resume 2> b.log &
    a=$!
    lowest=60
    # Watched until 10 frames were rendered again, then killed.
    while [ "$(pngs r.mp4.frames)" -lt 30 ]; do
        kill -0 "$a" 2>/dev/null || { cat b.log; fail "the resume ended before it was killed: nothing tested"; }
        n=$(frames_of r.mp4)
        [ "$n" != unplayable ] || fail "during the resume r.mp4 does not open: $(cat probe.err)"
        [ "$n" -ge "$lowest" ] || lowest=$n
        sleep 0.1
    done
    kill -9 "$a"
    set +e; wait "$a"; set -e
    [ "$lowest" = 60 ] || fail "during the resume r.mp4 played only $lowest of the earlier video's 60 frames"
    cmp -s r.mp4 whole.mp4 || fail "a resume killed before it caught up changed the earlier, complete video"
    # A resume of its own kill: the video again plays all 60 frames, the same as before.
    "$RAYFARM" "${film[@]}" -o r.mp4 --resume 2> c.log || { cat c.log; fail "second resume failed"; }
    cmp -s <(decoded r.mp4) <(decoded whole.mp4) || fail "the resumed video differs from the first run's"
    [ ! -e r.mp4.part ] || fail "r.mp4.part left after the resume"

    # Over a partial video (a kill -9 at about 30 frames): while the resume catches up, the
    # video never plays fewer frames than it did, and its frames are the film's.
    rm -rf p.mp4 p.mp4.*
    "$RAYFARM" "${film[@]}" -o p.mp4 2> p.log &
    a=$!
    wait_for_pngs p.mp4.frames 30 60
    kill -9 "$a"
    set +e; wait "$a"; set -e
    before=$(frames_of p.mp4)
    [ "$before" != unplayable ] && [ "$before" -ge 16 ] || fail "the killed run's video plays $before frames"
    "$RAYFARM" "${film[@]}" -o p.mp4 --resume 2> q.log &
    a=$!
    low=$before samples=0
    while kill -0 "$a" 2>/dev/null; do
        n=$(frames_of p.mp4)
        if [ "$n" != unplayable ]; then
            [ "$n" -ge "$low" ] || low=$n
            samples=$((samples + 1))
        elif kill -0 "$a" 2>/dev/null; then
            fail "during the resume p.mp4 does not open: $(cat probe.err)"
        fi
        sleep 0.1
    done
    wait "$a" || { cat q.log; fail "resume over the partial video failed"; }
    [ "$low" = "$before" ] || fail "during the resume p.mp4 dropped from $before to $low frames"
    [ "$samples" -ge 3 ] || fail "only $samples looks at the video during the resume"
    cmp -s <(decoded p.mp4) <(decoded whole.mp4) || fail "the video resumed over a partial one differs from the first run's"
    echo "resume: killed resume left the complete video byte for byte; over a partial video of $before frames, never fewer in $samples looks; both resumed videos the same as an uninterrupted run"
    ;;
mpi-2sigint)
    ranks_gone() {  # pids timeout-seconds: true once none of the pids runs
        local t=0
        while :; do
            local alive=0
            for p in $1; do kill -0 "$p" 2>/dev/null && alive=1; done
            [ "$alive" = 0 ] && return 0
            sleep 0.05; t=$((t + 1)); [ $t -lt $(($2 * 20)) ] || return 1
        done
    }
    two_sigints() {  # output
        setsid mpirun --oversubscribe -np 3 "$RAYFARM" "${film[@]}" -o "$1" > "$1.out" 2> "$1.err" &
        a=$!
        wait_for_pngs "$1.frames" 3 60
        ranks=$(pgrep -P "$a" | tr '\n' ' ')
        [ -n "$ranks" ] || fail "no ranks under mpirun $a"
        kill -INT "$a"
        sleep 0.1
        kill -INT "$a"
        set +e; wait "$a"; set -e
    }
    # The user waits for the prompt and reads: the line, the resume command, no lock.
    two_sigints m.mp4
    ranks_gone "$ranks" 10 || fail "ranks $ranks still run 10 s after mpirun ended"
    grep -Eq "^rayfarm: interrupted \(SIG(TERM|INT)\): the video m\.mp4 holds (no frames|frame 0|frames 0–[0-9]+) of 0–59.* \(playable\)$" m.mp4.err ||
        { cat m.mp4.err; fail "no interrupted line on mpirun's stderr"; }
    resume=$(sed -n 's/^rayfarm: to resume: //p' m.mp4.err)
    case "$resume" in mpirun\ *--resume) ;; *) cat m.mp4.err; fail "no resume command with mpirun on mpirun's stderr" ;; esac
    ls m.mp4.lock m.mp4.frames.lock 2>/dev/null && fail "a lock was left behind"
    line=$(grep "^rayfarm: interrupted" m.mp4.err)
    said=$(printf '%s\n' "$line" | sed -nE 's/.*holds frames 0–([0-9]+) of.*/\1/p; s/.*holds frame 0 of.*/0/p')
    said=$(( ${said:--1} + 1 ))
    n=$(frames_of m.mp4)
    [ "$n" = "$said" ] || fail "m.mp4 plays $n frames; the line says: $line"
    eval "$resume" 2> mr.log || { cat mr.log; fail "the printed resume command failed"; }
    [ "$(frames_of m.mp4)" = 60 ] || fail "resumed m.mp4 plays $(frames_of m.mp4) frames"
    # Impatient: the resume the moment mpirun's prompt comes back, the old ranks still ending.
    two_sigints q.mp4
    start=$(date +%s.%N)
    mpirun --oversubscribe -np 3 "$RAYFARM" "${film[@]}" -o q.mp4 --resume 2> qr.log || { cat qr.log; fail "a resume right after mpirun ended was refused or failed"; }
    [ "$(frames_of q.mp4)" = 60 ] || fail "resumed q.mp4 plays $(frames_of q.mp4) frames"
    ls q.mp4.lock q.mp4.frames.lock 2>/dev/null && fail "a lock was left after the resume"
    "$RAYFARM" "${film[@]}" -o ref.mp4 --no-frames 2> ref.log || { cat ref.log; fail "reference run failed"; }
    cmp -s <(decoded m.mp4) <(decoded ref.mp4) || fail "m.mp4 interrupted and resumed differs from an uninterrupted run"
    cmp -s <(decoded q.mp4) <(decoded ref.mp4) || fail "q.mp4 interrupted and resumed differs from an uninterrupted run"
    echo "mpi-2sigint: line ($said frames, playable) and resume command on mpirun's stderr, no lock left; printed resume and an immediate one both give the uninterrupted video"
    ;;
*) fail "unknown case $CASE" ;;
esac
