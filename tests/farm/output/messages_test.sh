#!/usr/bin/env bash
# Issue 46 #7: messages that name the file and the real problem. Real files on the real binary.
#   lock-dir   a folder left at OUT.mp4.lock: refused, exit 2, one line naming the folder as such
#              (not "basic_filebuf::underflow error reading the file: Is a directory")
#   checksums  the frames folder's checksum list deleted: the resume says it is missing, in one
#              note, renders the frames again and exits 0 (not "does not match the checksum
#              recorded" for every frame); a frame the list does not name is said to have none
#   stats-full --stats /dev/full fails after the film: the resume command printed leaves out
#              --stats /dev/full, says so, and works as printed
#   fifo-out   -o or --stats on a FIFO with no reader, render and still: refused at once, exit 2,
#              one line naming the FIFO (not blocked until a signal)
# Usage: messages_test.sh RAYFARM SOURCE_DIR WORK_DIR CASE
set -euo pipefail
RAYFARM=$1 SRC=$2 WORK=$3 CASE=$4
SCENE=$SRC/scenes/flight.json
rm -rf "$WORK"
mkdir -p "$WORK"
cd "$WORK"

. "$(dirname "$0")/../../lib/refusal.sh"  # fail, expect_refusal
export REFUSAL_TIMEOUT=20

r=("$RAYFARM" render "$SCENE" --size 32x18 --frames 0:3)

case "$CASE" in
lock-dir)
    mkdir OUT.mp4.lock
    expect_refusal --prefix "OUT.mp4.lock: is a directory, not a lock file; remove it if no render is writing OUT.mp4" "${r[@]}" -o OUT.mp4
    [ -d OUT.mp4.lock ] || fail "the folder at the lock was removed"
    [ ! -e OUT.mp4 ] || fail "a video was written"
    mkdir OUT2.mp4.frames.lock
    expect_refusal --prefix "OUT2.mp4.frames.lock: is a directory, not a lock file; remove it if no render is writing OUT2.mp4.frames" \
        "${r[@]}" -o OUT2.mp4
    echo "lock-dir: a folder at the video's or the frames' lock is named as a folder, exit 2"
    ;;
checksums)
    "${r[@]}" -o a.mp4 2> a.log || { cat a.log; fail "the first run failed"; }
    rm a.mp4.frames/rayfarm-frames.sha256
    "${r[@]}" -o a.mp4 --resume 2> resume.log || { cat resume.log; fail "the resume failed"; }
    grep -qx "rayfarm: note: a.mp4.frames/rayfarm-frames.sha256: missing, so the 4 kept frames cannot be checked; rendering them again" \
        resume.log || { cat resume.log; fail "no note that the checksum list is missing"; }
    [ "$(grep -c '^rayfarm: note:' resume.log)" -eq 1 ] || { cat resume.log; fail "expected one note"; }
    grep -q "does not match the checksum" resume.log && { cat resume.log; fail "a frame was said to mismatch a checksum that does not exist"; }
    grep -q "resume: 0 of 4 frames kept in a.mp4.frames, 4 to render" resume.log || { cat resume.log; fail "the frames were not rendered again"; }
    [ -s a.mp4.frames/rayfarm-frames.sha256 ] || fail "the checksum list was not written again"
    # One frame the list does not name (a run killed between writing it and listing it).
    "${r[@]}" -o b.mp4 2> b.log || { cat b.log; fail "the second run failed"; }
    grep -v ' frame_000002\.png$' b.mp4.frames/rayfarm-frames.sha256 > sums && mv sums b.mp4.frames/rayfarm-frames.sha256
    "${r[@]}" -o b.mp4 --resume 2> resume_b.log || { cat resume_b.log; fail "the resume of b failed"; }
    grep -qx "rayfarm: note: b.mp4.frames/frame_000002.png: no checksum recorded for it in b.mp4.frames/rayfarm-frames.sha256 (its run stopped before listing it); rendering it again" \
        resume_b.log || { cat resume_b.log; fail "no note that frame 2 has no checksum"; }
    grep -q "resume: 3 of 4 frames kept in b.mp4.frames, 1 to render" resume_b.log || { cat resume_b.log; fail "frame 2 was not rendered again"; }
    echo "checksums: a missing checksum list is named as missing, once, and a frame not listed as such; they are rendered again"
    ;;
stats-full)
    set +e
    "${r[@]}" -o a.mp4 --stats /dev/full 2> full.log
    status=$?
    set -e
    [ "$status" -eq 1 ] || { cat full.log; fail "exit status $status, expected 1"; }
    line=$(grep '^rayfarm: error: ' full.log) || { cat full.log; fail "no error line"; }
    case "$line" in
    "rayfarm: error: /dev/full: cannot write: No space left on device; finished frames are in a.mp4.frames; to resume without the --stats that could not be written: "*) ;;
    *) fail "unexpected message: $line" ;;
    esac
    cmd=${line##*could not be written: }
    case "$cmd" in *"/dev/full"*) fail "the resume command repeats the output that failed: $cmd" ;; esac
    case "$cmd" in *" -o a.mp4 --resume") ;; *) fail "unexpected resume command: $cmd" ;; esac
    eval "$cmd" 2> resume.log || { cat resume.log; fail "the printed resume command failed"; }
    grep -q "resume: 4 of 4 frames kept in a.mp4.frames, 0 to render" resume.log || { cat resume.log; fail "the resume rendered again"; }
    echo "stats-full: the resume command leaves out --stats /dev/full, says so, and works"
    ;;
fifo-out)
    mkfifo pipe.mp4 pipe.json pipe.png
    expect_refusal --prefix "pipe.mp4: cannot write: is a FIFO, not a regular file" "${r[@]}" -o pipe.mp4
    expect_refusal --prefix "pipe.json: cannot write: is a FIFO, not a regular file" "${r[@]}" -o a.mp4 --stats pipe.json
    expect_refusal --prefix "pipe.png: cannot write: is a FIFO, not a regular file" "$RAYFARM" still "$SCENE" --size 32x18 -o pipe.png
    expect_refusal --prefix "pipe.json: cannot write: is a FIFO, not a regular file" "$RAYFARM" still "$SCENE" --size 32x18 -o a.png --stats pipe.json
    [ -p pipe.mp4 ] && [ -p pipe.json ] && [ -p pipe.png ] || fail "a FIFO was replaced"
    [ ! -e a.mp4 ] && [ ! -e a.png ] || fail "an output was written"
    echo "fifo-out: -o and --stats on a FIFO refused at once, exit 2, by render and still"
    ;;
*) fail "unknown case $CASE" ;;
esac
