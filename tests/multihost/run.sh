#!/usr/bin/env bash
# rayfarm across three real network stacks: `bash tests/multihost/run.sh [RAYFARM] [WORK_DIR]`.
# Three network namespaces on a bridge (hosts.sh) play three hosts; Open MPI starts its daemons
# on them through netns_agent.sh in place of ssh, and every byte goes over TCP on 10.123.0.0/24.
#   1. pixel and frame mode on 3 hosts give PNGs bit-identical to one process, and the same
#      video file byte for byte (chunks of 4 frames, in frame mode encoded on the hosts that
#      render their frames, in pixel mode on the hosts that assembled them from every host's tiles);
#   2. kill -9 of the worker on farm2: the run stops, naming rank 1 and farm2;
#   3. farm3's link cut mid-chunk (frame mode, chunks of 8 frames rendered and encoded on the
#      hosts), at Open MPI's default keepalive and then with mpirun --enable-recovery and a short
#      keepalive (issue 45): the run names rank 2, farm3 and its chunk, gives its work to the
#      hosts left, and the film completes, the same file byte for byte as one uninterrupted
#      process gives; the shell gets control back within 25 s and farm3's processes end.
# Prints one summary line. Removes namespaces, bridge and name files even when a step fails;
# /etc/hosts is never touched (checked). Needs root; exits 77 (skipped) without it.
set -euo pipefail
SRC=$(cd "$(dirname "$0")/../.." && pwd)
RAYFARM=$(realpath "${1:-$SRC/build/bin/rayfarm}")
WORK=${2:-$SRC/build/test-output/multihost}
SCENE=$SRC/scenes/flight.json

if [ "$(id -u)" -ne 0 ] || ! command -v ip > /dev/null || ! command -v unshare > /dev/null; then
    echo "multihost: skipped: needs root, iproute2 and unshare to make network namespaces" >&2
    exit 77
fi
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 HWLOC_COMPONENTS=-gl
source "$SRC/tests/multihost/hosts.sh"
hosts_sum=$(sha256sum /etc/hosts)
finish() {
    local rc=$?
    hosts_down
    [ "$(sha256sum /etc/hosts)" = "$hosts_sum" ] || { echo "FAIL: /etc/hosts changed" >&2; rc=1; }
    exit $rc
}
trap finish EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

fail() { echo "FAIL: $*" >&2; exit 1; }
now() { echo "$EPOCHREALTIME"; }
since() { awk -v a="$1" -v b="${2:-$EPOCHREALTIME}" 'BEGIN { printf "%.1f\n", b - a }'; }
within() { awk -v a="$1" -v b="$2" 'BEGIN { exit !(a <= b) }'; }
# Runs a command in the background and notes when it ends (in $1.end), so that the time the
# shell got control back is measured, not the time this script got round to looking.
timed_bg() { local tag=$1; shift; { rc=0; "$@" || rc=$?; echo $rc > "$tag.rc"; echo "$EPOCHREALTIME" > "$tag.end"; } & }
ended() { cat "$1.rc"; }

rm -rf "$WORK"
mkdir -p "$WORK"
cd "$WORK"
printf 'farm1 slots=1\nfarm2 slots=1\nfarm3 slots=1\n' > hosts3
printf 'farm1 slots=1\nfarm2 slots=1\n' > hosts2
# TCP only, on the namespaces' own addresses. The OOB keepalive lets mpirun (and the daemon on a
# cut-off host) notice a dead link in seconds; Open MPI's default is 300 s + 9 × 20 s.
MCA=(--mca plm_rsh_agent "$AGENT" --mca btl tcp,self --mca btl_tcp_if_include "$SUBNET" --mca oob_tcp_if_include "$SUBNET")
KEEPALIVE=(--mca oob_tcp_keepalive_time 2 --mca oob_tcp_keepalive_intvl 1 --mca oob_tcp_keepalive_probes 3)
RECOVERY=()
farm() {  # hostfile np rayfarm-args...: mpirun on farm1, as a user logged in there would start it
    local hf=$1 np=$2
    shift 2
    on_host farm1 mpirun --hostfile "$hf" -np "$np" "${MCA[@]}" "${KEEPALIVE[@]}" "${RECOVERY[@]}" "$RAYFARM" "$@"
}
pngs_md5() { (cd "$1" && md5sum frame_*.png); }
frames_in() { ffprobe -v error -select_streams v:0 -count_frames -show_entries stream=nb_read_frames -of csv=p=0 "$1"; }
decoded_md5() { ffmpeg -v error -i "$1" -f framemd5 -pix_fmt rgb24 - | grep -v '^#' | awk -F, '{print $NF}'; }
wait_for_pngs() {  # dir count
    for _ in $(seq 600); do
        [ "$(ls "$1" 2> /dev/null | grep -c '^frame_.*\.png$')" -ge "$2" ] && return 0
        sleep 0.1
    done
    fail "fewer than $2 frames in $1 after 60 s"
}
wait_for_video() {  # file: until it plays at least one frame (a chunk reached it)
    for _ in $(seq 600); do
        [ "$(frames_in "$1" 2> /dev/null | awk '{print $1 + 0}')" -ge 1 ] 2> /dev/null && return 0
        sleep 0.1
    done
    fail "$1 plays no frame after 60 s"
}
pid_of_rank() {  # host rank -> pid of rayfarm's rank on that host
    local p
    for p in $(host_pids "$1"); do
        [ "$(cat /proc/"$p"/comm 2> /dev/null)" = rayfarm ] || continue
        tr '\0' '\n' < /proc/"$p"/environ 2> /dev/null | grep -qx "OMPI_COMM_WORLD_RANK=$2" && { echo "$p"; return; }
    done
}

start=$(now)
hosts_up
[ "$(on_host farm3 hostname)" = farm3 ] || fail "farm3 does not call itself farm3"

# 1. Bit-identical to one process, in both modes.
small=(render "$SCENE" --size 160x90 --frames 0:11 --chunk-frames 4)
"$RAYFARM" "${small[@]}" -o one.mp4 2> one.log || { cat one.log; fail "one-process run failed"; }
for mode in pixel frame; do
    farm hosts3 3 "${small[@]}" --mode "$mode" -o "$mode.mp4" 2> "$mode.log" || { cat "$mode.log"; fail "$mode run on 3 hosts failed"; }
    cmp -s <(pngs_md5 one.mp4.frames) <(pngs_md5 "$mode.mp4.frames") || fail "$mode mode on 3 hosts: PNGs differ from one process"
    [ "$(frames_in "$mode.mp4")" = 12 ] || fail "$mode mode on 3 hosts: the MP4 does not hold 12 frames"
    cmp -s one.mp4 "$mode.mp4" || fail "$mode mode on 3 hosts: the MP4 differs from one process's"
done
grep -q "video in chunks of 4 frames, each rendered and encoded by one rank" frame.log || { cat frame.log; fail "frame mode did not encode chunks on the hosts"; }
grep -q "video in chunks of 4 frames, each assembled from the tiles and encoded by one rank" pixel.log || { cat pixel.log; fail "pixel mode did not assemble chunks on the hosts"; }
echo "multihost: pixel and frame mode on farm1-3: 12 PNGs bit-identical to one process, the MP4 byte-identical"

# 2. A remote worker killed.
long=(render "$SCENE" --size 320x180 --spp 16 --frames 0:47 --timeout 3 --lossless --mode frame --chunk-frames 8)
timed_bg kill farm hosts3 3 "${long[@]}" -o kill.mp4 2> kill.log
job=$!
# Killed once a chunk is in the video: with chunks of 8 frames, two PNGs can be the first frames
# of two chunks, and when mpirun ends the job before the survivor finishes one (a busy machine)
# the video rightly holds nothing.
wait_for_video kill.mp4
victim=$(pid_of_rank farm2 1)
[ -n "$victim" ] || fail "rank 1 is not on farm2"
t0=$(now)
kill -9 "$victim"
wait "$job" || true
rc=$(ended kill)
kill_s=$(since "$t0" "$(cat kill.end)")
[ "$rc" -ne 0 ] || fail "a run whose worker was killed exited 0"
# rank 0 names the lost rank itself, or, when Open MPI held it inside MPI (a broken TCP peer
# reported through mpirun), mpirun does; either way rank 0 must leave a playable video.
grep -Eq "rayfarm: error: rank 1 on farm2 .*frame|process rank 1 with PID [0-9]+ on node farm2 exited on signal 9" kill.log ||
    { cat kill.log; fail "the stop does not name rank 1 on farm2"; }
grep -Eq "^rayfarm: (error|interrupted).*the video kill.mp4 holds frames? .*\(playable\)" kill.log || { cat kill.log; fail "rank 0 did not finish the video"; }
within "$kill_s" 10 || fail "took $kill_s s to stop after kill -9 (bound 10 s)"
played=$(frames_in kill.mp4)
[ "$played" -ge 1 ] || fail "the video of the killed run does not play"
echo "multihost: kill -9 of rank 1 on farm2: stopped in $kill_s s, MP4 plays $played frames:" \
     "$(grep -Eo 'rank 1 on farm2 .{0,60}|process rank 1 with PID [0-9]+ on node farm2 exited on signal 9' kill.log | head -1)"

# 3a. farm3's cable pulled, Open MPI at its default keepalive (a user's plain mpirun). rank 0
# names the lost host and gives its chunk to the hosts left (issue 45): the film completes, the
# same file as one process makes. mpirun would then wait minutes for its daemon on farm3, so
# rank 0's reaper ends it; the worker on farm3 leaves its silent master by itself (after 2 x 3 s).
# Open MPI's daemon there lingers until its own keepalive (minutes): it is ended here, and counted.
"$RAYFARM" "${long[@]}" -o whole.mp4 2> whole.log || { cat whole.log; fail "uninterrupted run failed"; }
saved=("${KEEPALIVE[@]}")
KEEPALIVE=()
timed_bg cut0 farm hosts3 3 "${long[@]}" -o cut0.mp4 2> cut0.log
job=$!
wait_for_pngs cut0.mp4.frames 3
# Rank 2's own process, looked up while it surely runs: a lookup by namespace during the cut can
# come back empty for a moment (`ip netns pids` while processes come and go), which is not the
# worker leaving.
rank2=""
for _ in $(seq 20); do rank2=$(pid_of_rank farm3 2); [ -n "$rank2" ] && break; sleep 0.1; done
[ -n "$rank2" ] || fail "default keepalive: no rank 2 on farm3 before the cut"
runs() { [ "$(cat /proc/"$1"/comm 2> /dev/null)" = rayfarm ]; }
t0=$(now)
cut_link farm3
named_s=""
for _ in $(seq 300); do
    [ -z "$named_s" ] && grep -q "rank 2 on farm3 stopped answering" cut0.log && named_s=$(since "$t0")
    runs "$rank2" || break
    sleep 0.1
done
worker_s=$(since "$t0")
! runs "$rank2" && within "$worker_s" 12 || fail "rank 2 still runs on farm3 $worker_s s after the cut (bound 2 x 3 s + 6 s)"
( sleep 40; kill -9 $(host_pids farm1) 2> /dev/null ) > /dev/null 2>&1 &  # a guard, should the test fail
guard=$!
wait "$job" || true
[ -f cut0.end ] || fail "default keepalive: mpirun had not returned 40 s after the cut"
shell0_s=$(since "$t0" "$(cat cut0.end)")
kill "$guard" 2> /dev/null || true
grep -q "rayfarm: warning: rank 2 on farm3 stopped answering .*its work goes to the 1 rendering rank left" cut0.log ||
    { cat cut0.log; fail "default keepalive: no line naming rank 2 on farm3 and where its work went"; }
grep -q "^rayfarm: wrote cut0.mp4: 48 frames" cut0.log || { cat cut0.log; fail "default keepalive: the film did not complete"; }
cmp -s whole.mp4 cut0.mp4 || fail "default keepalive: the video differs from one uninterrupted process's"
within "$shell0_s" 25 || fail "default keepalive: mpirun returned $shell0_s s after the cut (bound 25 s)"
left=$(host_pids farm3 | xargs -r ps -o comm= -p | sort | uniq -c | xargs)
kill -9 $(host_pids farm2) $(host_pids farm3) 2> /dev/null || true
restore_link farm3
KEEPALIVE=("${saved[@]}")
echo "multihost: farm3 cut off, default keepalive: named after ${named_s:-?} s, film completed byte-identical, shell back in $shell0_s s," \
     "farm3's worker left by itself in $worker_s s; left on farm3: ${left:-nothing}"

# 3. farm3's cable pulled mid-run (issue 14 #6), under mpirun --enable-recovery (issue 45), which
# keeps the job going when its daemon on farm3 is lost (the short keepalive finds that out).
RECOVERY=(--enable-recovery)
timed_bg cut farm hosts3 3 "${long[@]}" -o cut.mp4 2> cut.log
job=$!
wait_for_pngs cut.mp4.frames 3
t0=$(now)
cut_link farm3
( sleep 60; kill -9 $(host_pids farm1) 2> /dev/null ) > /dev/null 2>&1 &  # a guard, should the test fail
guard=$!
wait "$job" || true
kill "$guard" 2> /dev/null || true
shell_s=$(since "$t0" "$(cat cut.end)")
# Empty twice, 0.2 s apart: one lookup during the exits can come back empty for a moment.
host_empty() { [ -z "$(host_pids "$1")" ] && sleep 0.2 && [ -z "$(host_pids "$1")" ]; }
for _ in $(seq 300); do host_empty farm3 && break; sleep 0.1; done
gone_s=$(since "$t0")
host_empty farm3 && within "$gone_s" 30 ||
    fail "processes still on farm3 $gone_s s after its link went down: $(host_pids farm3 | xargs -r ps -o comm= -p | tr '\n' ' ')"
within "$shell_s" 25 || fail "mpirun returned $shell_s s after the cut (bound 25 s)"
grep -Eq "rayfarm: warning: rank 2 on farm3 stopped answering .*while rendering frame [0-9]+ of chunk [0-9]+" cut.log ||
    { cat cut.log; fail "the warning does not name rank 2 on farm3 and its chunk"; }
cut_chunk=$(grep -Eo "of chunk [0-9]+ \(frames [0-9]+–[0-9]+\)" cut.log | head -1)
grep -q "^rayfarm: wrote cut.mp4: 48 frames" cut.log || { cat cut.log; fail "--enable-recovery: the film did not complete"; }
cmp -s whole.mp4 cut.mp4 || fail "--enable-recovery: the video differs from one uninterrupted process's"
echo "multihost: PASS in $(since "$start") s: 3 hosts bit-identical to 1 process; killed worker stopped in $kill_s s;" \
     "farm3 cut off mid-chunk ($cut_chunk) under --enable-recovery: film completed byte-identical, shell back in $shell_s s, farm3 empty in $gone_s s"
