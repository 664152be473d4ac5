#!/usr/bin/env bash
# Issue 30 #2: a timeline of 10⁹ frames is a range, never a per-frame set. Under a 3 GB address
# space limit (per-frame sets took 22 GB before the fix), `render` of the whole film starts
# writing frames within seconds and stays small; a short --frames range of it renders to a video
# of exactly those frames; --resume over it counts the kept frames at once.
# Usage: long_timeline_test.sh RAYFARM SOURCE_DIR WORK_DIR
set -euo pipefail
RAYFARM=$1 SRC=$2 WORK=$3
rm -rf "$WORK" && mkdir -p "$WORK" && cd "$WORK"
fail() { echo "FAIL: $*" >&2; exit 1; }
LIMIT_KB=3000000  # ulimit -v
MAX_RSS_KB=400000

python3 - "$SRC/scenes/whitted.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
s["render"].update(width=48, height=36, spp=16)
s["timeline"] = {"frames": 1000000000, "fps": 30, "animation": False,
                 "camera": {"orbit": {"center": [0, 0, 0], "radius": 8, "height": 3, "period": 1}}}
json.dump(s, open("long.json", "w"))
PY

# A short range of the long film: the video has exactly its frames.
(ulimit -v $LIMIT_KB; timeout 60 "$RAYFARM" render long.json -o part.mp4 --frames 500000000:500000002) 2> part.err ||
    { cat part.err; fail "a 3-frame range of a 10⁹-frame timeline did not render"; }
n=$(ffprobe -v error -select_streams v:0 -count_frames -show_entries stream=nb_read_frames -of csv=p=0 part.mp4)
[ "$n" = 3 ] || fail "part.mp4 has $n frames, not 3"
ls part.mp4.frames/frame_500000000.png part.mp4.frames/frame_500000002.png > /dev/null || fail "frames 500000000 and 500000002 not kept"

# The whole film: frames appear within seconds, memory stays small; Ctrl-C stops it.
# Options: passed on; leaves the run's pid in $pid once 3 more frames appeared.
frames_kept() { { ls whole.mp4.frames 2> /dev/null || true; } | grep -c '^frame_.*\.png$' || true; }
start_whole() {
    local before
    before=$(frames_kept)
    (ulimit -v $LIMIT_KB; exec "$RAYFARM" render long.json -o whole.mp4 "$@") 2> whole.err &
    pid=$!
    local t0=$SECONDS
    while [ "$(frames_kept)" -lt $((before + 3)) ]; do
        kill -0 $pid 2> /dev/null || { cat whole.err; fail "render of the whole film ended before writing 3 frames"; }
        [ $((SECONDS - t0)) -lt 20 ] || { kill -KILL $pid; cat whole.err; fail "no 3 frames after 20 s"; }
        sleep 0.1
    done
    local rss
    rss=$(awk '/^VmHWM/ {print $2}' /proc/$pid/status)
    echo "peak RSS ${rss} kB $(( SECONDS - t0 )) s after start"
    [ "$rss" -lt $MAX_RSS_KB ] || { kill -KILL $pid; fail "peak RSS $rss kB >= $MAX_RSS_KB kB"; }
}
stop_whole() {
    kill -INT $pid
    local rc=0
    wait $pid || rc=$?
    [ $rc = 130 ] || { cat whole.err; fail "exit $rc after Ctrl-C, not 130"; }
    grep -q "interrupted (SIGINT)" whole.err || { cat whole.err; fail "no interruption line"; }
}
start_whole
stop_whole
kept=$(frames_kept)
start_whole --resume
grep -Eq "resume: [0-9]+ of 1000000000 frames kept" whole.err || { cat whole.err; fail "no resume line counting 10⁹ frames"; }
stop_whole
echo "PASS: 10⁹-frame timeline: a 3-frame range rendered; the whole film started at once, twice ($kept frames kept)"
