#!/usr/bin/env bash
# Issue 47 #4: the progress line says frames rendered and encoded, the rate, the ETA and the
# workers alive and busy; a bar under a terminal (script), one plain line per interval into a
# file. Rendered never trails encoded, and it moves frame by frame while chunks of frames are
# encoded at once. One process, and mpirun -np 3 in frame and pixel mode.
#   progress_test.sh RAYFARM SOURCE_DIR OUT_DIR
set -euo pipefail
rayfarm=$1 src=$2 out=$3
fail() { echo "FAIL: $*" >&2; exit 1; }
rm -rf "$out" && mkdir -p "$out" && cd "$out"
scene=$src/scenes/whitted.json
# 24 frames in chunks of 8, slow enough for several lines 0.02 s apart.
film=(--size 128x72 --spp 9 --frames 0:23 --chunk-frames 8 --no-frames)
export RAYFARM_PROGRESS_SECONDS=0.02

# check_lines FILE TOTAL ALIVE tty|file [per-frame]: every progress line in FILE has the words, counts that
# only grow, rendered ≥ encoded, the total and the workers alive; with per-frame, rendered takes
# values between chunk boundaries (not only multiples of 8).
check_lines() {
    python3 - "$@" <<'PY'
import re, sys
path, total, alive, kind = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
per_frame = len(sys.argv) > 5
text = open(path, encoding="utf-8", errors="replace", newline="").read()
line_re = re.compile(r"(?:rayfarm: |\r\x1b\[K\[([#=.]+)\] )(\d+)/(\d+) rendered, (\d+) encoded, (\d+\.\d) fps, "
                     r"ETA (--|\d+:\d\d), (\d+)/(\d+) workers busy")
found = [m for m in line_re.finditer(text)]
assert found, f"{path}: no progress line in:\n{text}"
last_r = last_e = 0
rendered_values = set()
for m in found:
    bar, r, t, e, fps, eta, busy, a = m.groups()
    r, t, e, a, busy = int(r), int(t), int(e), int(a), int(busy)
    assert t == total, (m.group(0), total)
    assert r >= e, f"rendered < encoded: {m.group(0)}"
    assert r >= last_r and e >= last_e, f"a count went back: {m.group(0)}"
    assert a == alive and 0 <= busy <= a, f"expected {alive} workers alive: {m.group(0)}"
    last_r, last_e = r, e
    rendered_values.add(r)
    assert (bar is not None) == (kind == "tty"), f"{kind}: {m.group(0)!r}"
    if bar is not None:
        width = len(bar)  # '#' encoded, '=' rendered and not yet encoded, '.' the rest
        assert bar.count("#") == e * width // t and bar.count("#") + bar.count("=") == max(e, r) * width // t, (bar, r, e)
print(f"{path}: {len(found)} lines, rendered took {sorted(rendered_values)}")
if per_frame:
    between = [v for v in rendered_values if v % 8 and 0 < v < total]
    assert between, f"rendered moved only by chunks: {sorted(rendered_values)}"
PY
}

# Into a file: plain lines, no bar, no carriage return or escape.
"$rayfarm" render "$scene" -o file.mp4 "${film[@]}" 2> file.err || { cat file.err; fail "render exited $?"; }
grep -q "rayfarm: [0-9]*/24 rendered" file.err || { cat file.err; fail "into a file: no progress line"; }
! grep -q $'\r\|\033' file.err || fail "into a file: a carriage return or escape in the log"
! grep -q "\] [0-9]*/24 rendered" file.err || fail "into a file: a bar"
check_lines file.err 24 1 file || fail "into a file: bad progress lines"
echo "ok: into a file"

# Under a terminal (script, 80 columns): the live line with its bar, rewritten in place.
script -qec "$rayfarm render $scene -o tty.mp4 ${film[*]}" /dev/null > tty.out 2>&1 || { cat tty.out; fail "render under script exited $?"; }
grep -q $'\r\033\[K'"\[[#=.]*\] [0-9]*/24 rendered" tty.out || { cat -v tty.out | head; fail "under a terminal: no live line with a bar"; }
check_lines tty.out 24 1 tty || fail "under a terminal: bad progress lines"
echo "ok: under a terminal"

# mpirun -np 3: rank 0 schedules, two ranks render and encode chunks, so encoded moves by 8
# while rendered moves frame by frame.
if command -v mpirun >/dev/null; then
    for mode in frame pixel; do
        mpirun --oversubscribe -np 3 "$rayfarm" render "$scene" -o "mpi_$mode.mp4" "${film[@]}" --mode "$mode" 2> "mpi_$mode.err" ||
            { cat "mpi_$mode.err"; fail "mpirun -np 3 --mode $mode exited $?"; }
        check_lines "mpi_$mode.err" 24 2 file per-frame || fail "mpirun -np 3 --mode $mode: bad progress lines"
    done
    echo "ok: mpirun -np 3, frame and pixel mode"
fi
echo "PASS"
