#!/usr/bin/env bash
# Issue 46: nothing mixed, nothing hung. Real renders on the real binary.
#   identity  12 frames, the last 6 deleted: --resume with --environment-rotation 90 is refused
#             naming the setting with its old and new values, the kept frames and the video
#             untouched; the same options resume to the frames of a run never interrupted
#   fifo      a FIFO and a directory in place of kept PNGs, a FIFO in place of a kept EXR: the
#             resume neither hangs nor fails; each is noted, rendered again (the directory moved
#             aside, its contents kept), and the frames are an uninterrupted run's; a FIFO in
#             place of the checksum list is refused
#   own-files outputs named after the run's own files (a kept frame, the manifest, the locks, the
#             remux's temporary file) refused with exit 2 and one line before anything renders:
#             the frames, the manifest and the video untouched, no lock left; then a resume runs
# Usage: kept_frames_test.sh RAYFARM SOURCE_DIR WORK_DIR CASE
set -euo pipefail
RAYFARM=$1 SRC=$2 WORK=$3 CASE=$4
SCENE=$SRC/scenes/flight.json
rm -rf "$WORK"
mkdir -p "$WORK"
cd "$WORK"

. "$(dirname "$0")/../../lib/refusal.sh"  # fail, expect_refusal
pngs() { (cd "$1" && sha256sum frame_*.png); }

r=("$RAYFARM" render "$SCENE" --size 32x18 --frames 0:11)

case "$CASE" in
identity)
    "${r[@]}" -o full.mp4 2> full.log || { cat full.log; fail "the uninterrupted run failed"; }
    "${r[@]}" -o a.mp4 2> a.log || { cat a.log; fail "the first run failed"; }
    rm a.mp4.frames/frame_0000{06,07,08,09,10,11}.png
    kept=$(pngs a.mp4.frames) video=$(sha256sum < a.mp4)
    expect_refusal "a.mp4.frames: cannot resume: its frames were rendered with other settings (environment_rotation was not given, now 90.0)" \
        "${r[@]}" -o a.mp4 --resume --environment-rotation 90
    expect_refusal "a.mp4.frames: cannot resume: its frames were rendered with other settings (ground was not given, now \"shadow\")" \
        "${r[@]}" -o a.mp4 --resume --ground shadow
    [ "$(pngs a.mp4.frames)" = "$kept" ] || fail "a refused resume touched the kept frames"
    [ "$(sha256sum < a.mp4)" = "$video" ] || fail "a refused resume touched the video"
    "${r[@]}" -o a.mp4 --resume 2> resume.log || { cat resume.log; fail "the resume with the same options failed"; }
    grep -q "resume: 6 of 12 frames kept in a.mp4.frames, 6 to render" resume.log || { cat resume.log; fail "did not render the 6 missing frames"; }
    [ "$(pngs a.mp4.frames)" = "$(pngs full.mp4.frames)" ] || fail "the resumed frames differ from an uninterrupted run's"
    cmp -s a.mp4 full.mp4 || fail "the resumed video differs from an uninterrupted run's"
    echo "identity: a resume with another picture setting refused naming it, old and new; the same options complete"
    ;;
fifo)
    "${r[@]}" -o full.mp4 --frames-format exr 2> full.log || { cat full.log; fail "the uninterrupted run failed"; }
    "${r[@]}" -o a.mp4 --frames-format exr 2> a.log || { cat a.log; fail "the first run failed"; }
    rm a.mp4.frames/frame_000006.png a.mp4.frames/frame_000009.png a.mp4.frames/frame_000003.exr
    mkfifo a.mp4.frames/frame_000006.png a.mp4.frames/frame_000003.exr
    mkdir -p a.mp4.frames/frame_000009.png/inside
    echo keep > a.mp4.frames/frame_000009.png/inside/note.txt
    # Without the check the resume waits for a writer on the FIFO for good (and ignores SIGTERM).
    set +e
    timeout -s KILL 60 "${r[@]}" -o a.mp4 --frames-format exr --resume 2> resume.log
    status=$?
    set -e
    [ "$status" -eq 0 ] || { cat resume.log; fail "the resume over a FIFO and a directory exited $status"; }
    grep -qF "note: a.mp4.frames/frame_000006.png: is a FIFO, not a frame (removed); rendering it again" resume.log || { cat resume.log; fail "no note on the FIFO"; }
    grep -qF "note: a.mp4.frames/frame_000009.png: is a directory, not a frame (moved to a.mp4.frames/frame_000009.png.not-a-frame); rendering it again" resume.log ||
        { cat resume.log; fail "no note on the directory"; }
    grep -qF "note: a.mp4.frames/frame_000003.exr: is a FIFO, not a frame (removed); rendering it again" resume.log || { cat resume.log; fail "no note on the EXR FIFO"; }
    grep -q "resume: 9 of 12 frames kept in a.mp4.frames, 3 to render" resume.log || { cat resume.log; fail "did not render the 3 damaged frames"; }
    [ "$(cat a.mp4.frames/frame_000009.png.not-a-frame/inside/note.txt)" = keep ] || fail "the directory's contents were lost"
    [ "$(pngs a.mp4.frames)" = "$(pngs full.mp4.frames)" ] || fail "the resumed frames differ from an uninterrupted run's"
    cmp -s a.mp4.frames/frame_000003.exr full.mp4.frames/frame_000003.exr || fail "the EXR frame rendered again differs"
    cmp -s a.mp4 full.mp4 || fail "the resumed video differs from an uninterrupted run's"
    rm a.mp4.frames/rayfarm-frames.sha256 && mkfifo a.mp4.frames/rayfarm-frames.sha256
    expect_refusal "a.mp4.frames/rayfarm-frames.sha256: is a FIFO, not the frames' checksum list" "${r[@]}" -o a.mp4 --frames-format exr --resume
    echo "fifo: a FIFO or a directory in place of a kept frame is noted and rendered again, no hang"
    ;;
own-files)
    "${r[@]}" -o a.mp4 2> a.log || { cat a.log; fail "the first run failed"; }
    rm a.mp4.frames/frame_000011.png
    kept=$(cd a.mp4.frames && sha256sum frame_*.png rayfarm-frames.json rayfarm-frames.sha256) video=$(sha256sum < a.mp4)
    expect_refusal "a.mp4.frames/frame_000003.png: --stats names a frame kept in the frames folder (a.mp4.frames); choose another name" \
        "${r[@]}" -o a.mp4 --stats a.mp4.frames/frame_000003.png --overwrite
    expect_refusal "a.mp4.frames/rayfarm-frames.json: --stats names the frames folder's manifest (a.mp4.frames); choose another name" \
        "${r[@]}" -o a.mp4 --stats a.mp4.frames/rayfarm-frames.json --resume
    expect_refusal "a.mp4.lock: --stats names the lock this run holds on -o (a.mp4); choose another name" \
        "${r[@]}" -o a.mp4 --stats a.mp4.lock --resume
    expect_refusal "a.mp4.remux: --frames-dir names the temporary file the video (a.mp4) is remuxed through; choose another name" \
        "${r[@]}" -o a.mp4 --frames-dir a.mp4.remux --overwrite
    expect_refusal "a.mp4.frames/frame_000001.png: --poster names a frame kept in the frames folder (a.mp4.frames)" \
        "${r[@]}" -o a.mp4 --poster a.mp4.frames/frame_000001.png --resume
    expect_refusal "a.mp4.frames.lock: --stats names the lock this run holds on its frames folder (a.mp4.frames)" \
        "${r[@]}" -o a.mp4 --stats a.mp4.frames.lock --resume
    [ "$(cd a.mp4.frames && sha256sum frame_*.png rayfarm-frames.json rayfarm-frames.sha256)" = "$kept" ] || fail "a refused run touched the frames folder"
    [ "$(sha256sum < a.mp4)" = "$video" ] || fail "a refused run touched the video"
    for f in a.mp4.lock a.mp4.frames.lock a.mp4.remux; do [ ! -e "$f" ] || fail "a refused run left $f"; done
    "${r[@]}" -o a.mp4 --resume --stats a.mp4.frames/stats.json 2> resume.log || { cat resume.log; fail "the resume after the refusals failed"; }
    grep -q "resume: 11 of 12 frames kept in a.mp4.frames, 1 to render" resume.log || { cat resume.log; fail "the resume did not find the kept frames"; }
    echo "own-files: outputs naming the run's own files refused before rendering, nothing touched"
    ;;
*)
    fail "unknown case $CASE"
    ;;
esac
