#!/usr/bin/env bash
# Issue 14 #2: every output write is checked (and #9: a size the encoder cannot take is refused). A write that fails (/dev/full, a full file system)
# must exit 1 with one line naming the file and the OS's reason, never "wrote" over an empty file.
# Usage: output_write_test.sh RAYFARM SOURCE_DIR WORK_DIR
set -euo pipefail
RAYFARM=$1 SRC=$2 WORK=$3
SCENE="$SRC/scenes/flight.json"
mkdir -p "$WORK"
cd "$WORK"
fail() { echo "FAIL: $*" >&2; exit 1; }

expect_write_error() {  # name file log rc
    [ "$4" = 1 ] || { cat "$3"; fail "$1: exit $4, expected 1"; }
    grep -q "^rayfarm: error: $2: cannot write: No space left on device$" "$3" || { cat "$3"; fail "$1: no error naming $2 and the reason"; }
    [ "$(grep -c 'rayfarm: error' "$3")" = 1 ] || { cat "$3"; fail "$1: expected one error line"; }
    if grep -q "rayfarm: wrote $2" "$3"; then fail "$1: claims to have written $2"; fi
}

set +e; "$RAYFARM" still "$SCENE" --size 32x24 -o /dev/full 2> full_png.log; rc=$?; set -e
expect_write_error "still -o /dev/full" /dev/full full_png.log "$rc"
set +e; "$RAYFARM" still "$SCENE" --size 32x24 -o ok.png --stats /dev/full 2> full_stats.log; rc=$?; set -e
expect_write_error "still --stats /dev/full" /dev/full full_stats.log "$rc"
echo "dev-full: PNG and --stats writes to /dev/full exit 1 naming the file and ENOSPC"

# A real full file system: a 64 KiB tmpfs, if this machine lets us mount one (root in a
# container with CAP_SYS_ADMIN); the PNG of a 400x300 frame does not fit.
mnt="$WORK/small-fs"
mkdir -p "$mnt"
if mount -t tmpfs -o size=64k tmpfs "$mnt" 2>/dev/null; then
    trap 'umount "$mnt" 2>/dev/null || true' EXIT
    head -c 60000 /dev/zero > "$mnt/filler" || true
    set +e; "$RAYFARM" still "$SCENE" --size 400x300 -o "$mnt/big.png" 2> disk_png.log; rc=$?; set -e
    expect_write_error "still into a full tmpfs" "$mnt/big.png" disk_png.log "$rc"
    echo "full-disk: still into a full tmpfs exits 1 naming the file and ENOSPC"
    # Issue 14 #9: frames filling the disk mid-run: no .part left, the reason, and how to resume.
    rm -f "$mnt/filler"
    set +e; "$RAYFARM" render "$SCENE" --size 320x180 -o full.mp4 --frames-dir "$mnt/frames" 2> disk_render.log; rc=$?; set -e
    [ "$rc" = 1 ] || { cat disk_render.log; fail "render onto a full disk: exit $rc, expected 1"; }
    [ "$(grep -c 'rayfarm: error' disk_render.log)" = 1 ] || { cat disk_render.log; fail "render onto a full disk: expected one error line"; }
    # One form whichever thread saw the failure first: the file and the reason, what the video
    # holds, where the frames are and how to resume.
    grep -Eq "^rayfarm: error: $mnt/frames/frame_[0-9]*\.png.*: cannot write: No space left on device; the video full\.mp4 holds (frames? [0-9–]+|no frames) of 0–96; finished frames are in $mnt/frames; to resume: .*--resume\$" disk_render.log ||
        { cat disk_render.log; fail "render onto a full disk: no file, reason or resume command"; }
    if ls "$mnt/frames" | grep -q '\.part$'; then fail "render onto a full disk left a .part file"; fi
    echo "full-disk: render stops with the file, ENOSPC and the resume command; no .part left"
else
    echo "full-disk: SKIPPED (cannot mount a tmpfs here)"
fi

# Issue 14 #9: a size FFmpeg cannot encode is refused before rendering, in one line, exit 2.
set +e; "$RAYFARM" render "$SCENE" -o big.mp4 --size 16384x16384 2> big.log; rc=$?; set -e
[ "$rc" = 2 ] || { cat big.log; fail "16384x16384: exit $rc, expected 2"; }
[ "$(wc -l < big.log)" = 1 ] && grep -q "^rayfarm: error: --size 16384x16384: too large" big.log || { cat big.log; fail "16384x16384: not one error line"; }
echo "size: 16384x16384 refused before rendering with exit 2"
