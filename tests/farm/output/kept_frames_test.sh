#!/usr/bin/env bash
# Issue 46: nothing mixed, nothing hung. Real renders on the real binary.
#   identity  12 frames, the last 6 deleted: --resume with --environment-rotation 90 is refused
#             naming the setting with its old and new values, the kept frames and the video
#             untouched; the same options resume to the frames of a run never interrupted
# Usage: kept_frames_test.sh RAYFARM SOURCE_DIR WORK_DIR CASE
set -euo pipefail
RAYFARM=$1 SRC=$2 WORK=$3 CASE=$4
SCENE=$SRC/scenes/flight.json
rm -rf "$WORK"
mkdir -p "$WORK"
cd "$WORK"

fail() { echo "FAIL: $*" >&2; exit 1; }
# A usage error: exactly one line "rayfarm: error: ...PATTERN..." and exit status 2.
expect_refusal() {  # pattern command...
    local pattern=$1 err status
    shift
    set +e
    err=$(timeout 60 "$@" 2>&1 >/dev/null)
    status=$?
    set -e
    [ "$status" -eq 2 ] || fail "$*: exit status $status, expected 2 ($err)"
    [ "$(printf '%s\n' "$err" | wc -l)" -eq 1 ] || fail "$*: expected one error line, got: $err"
    case "$err" in "rayfarm: error: "*"$pattern"*) ;; *) fail "$*: unexpected message: $err" ;; esac
}
pngs() { (cd "$1" && sha256sum frame_*.png); }

r=("$RAYFARM" render "$SCENE" --size 32x18 --frames 0:11)

case "$CASE" in
identity)
    "${r[@]}" -o full.mp4 2> full.log || { cat full.log; fail "the uninterrupted run failed"; }
    "${r[@]}" -o a.mp4 2> a.log || { cat a.log; fail "the first run failed"; }
    rm a.frames/frame_0000{06,07,08,09,10,11}.png
    kept=$(pngs a.frames) video=$(sha256sum < a.mp4)
    expect_refusal "a.frames: cannot resume: its frames were rendered with other settings (environment_rotation was not given, now 90.0)" \
        "${r[@]}" -o a.mp4 --resume --environment-rotation 90
    expect_refusal "a.frames: cannot resume: its frames were rendered with other settings (ground was not given, now \"shadow\")" \
        "${r[@]}" -o a.mp4 --resume --ground shadow
    [ "$(pngs a.frames)" = "$kept" ] || fail "a refused resume touched the kept frames"
    [ "$(sha256sum < a.mp4)" = "$video" ] || fail "a refused resume touched the video"
    "${r[@]}" -o a.mp4 --resume 2> resume.log || { cat resume.log; fail "the resume with the same options failed"; }
    grep -q "resume: 6 of 12 frames kept in a.frames, 6 to render" resume.log || { cat resume.log; fail "did not render the 6 missing frames"; }
    [ "$(pngs a.frames)" = "$(pngs full.frames)" ] || fail "the resumed frames differ from an uninterrupted run's"
    cmp -s a.mp4 full.mp4 || fail "the resumed video differs from an uninterrupted run's"
    echo "identity: a resume with another picture setting refused naming it, old and new; the same options complete"
    ;;
*)
    fail "unknown case $CASE"
    ;;
esac
