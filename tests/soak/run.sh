#!/usr/bin/env bash
# Memory over a long film: `bash tests/soak/run.sh RAYFARM WORK_DIR [FRAMES [SIZE [opt-in]]]`
# renders FRAMES frames (default 3600: two minutes of video at 30 fps) of SIZE (default 160x90)
# at 1 spp under
# `mpirun -np 3` in frame mode, keeping PNG frames, and samples the resident set (VmRSS) of every
# rank once a second (SOAK_PERIOD seconds; the smoke run samples four times a second, so a quick
# machine still gives it enough samples), with the size of the video written so far. The warm-up
# lasts until the video holds a tenth of its final size (and at least a fifth of the samples, at
# least 3): under load, start-up (the encoder's buffers, the first frames) takes longer than any
# fixed share of the samples. After it, no
# rank's RSS may grow more than 5% over its level at the end of the warm-up, up to 3 samples before
# the end (the close, with rank 0's remux, is left out): a leak per frame or per message shows
# as steady growth. Also checks the video holds every frame.
# The default suite runs a 2400-frame 128x72 smoke version; the full one (5th argument opt-in) runs with
# RAYFARM_SOAK=1: RAYFARM_SOAK=1 ctest -R soak_rss_3600.
set -euo pipefail
RAYFARM=$1 WORK=$2 FRAMES=${3:-3600} SIZE=${4:-160x90}
if [ "${5:-}" = opt-in ] && [ "${RAYFARM_SOAK:-0}" != 1 ]; then
    echo "soak: skipped (opt-in: RAYFARM_SOAK=1)"
    exit 77
fi
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
SRC=$(cd "$(dirname "$0")/../.." && pwd)
fail() { echo "FAIL: $*" >&2; exit 1; }
mkdir -p "$WORK"
cd "$WORK"
rm -rf soak.* rss.csv

# flight.json's 4 s flight, slowed to last FRAMES frames at 30 fps.
python3 - "$SRC/scenes/flight.json" "$FRAMES" <<'PY'
import json, sys
d = json.load(open(sys.argv[1]))
frames = int(sys.argv[2])
tl = d["timeline"]
scale = (frames - 1) / 30.0 / tl["duration"]  # the last frame sits at the duration
def stretch(v):
    if isinstance(v, dict):
        return {k: (x * scale if k == "time" else stretch(x)) for k, x in v.items()}
    if isinstance(v, list):
        return [stretch(x) for x in v]
    return v
d["timeline"] = stretch({k: v for k, v in tl.items() if k not in ("fps", "duration")})
d["timeline"]["fps"], d["timeline"]["duration"] = 30, (frames - 1) / 30.0
json.dump(d, open("soak.json", "w"))
PY

mpirun --oversubscribe -np 3 "$RAYFARM" render soak.json -o soak.mp4 --size "$SIZE" --spp 1 --mode frame 2> soak.log &
pid=$!
# One sample a period of every rank's VmRSS (kB), by the ranks' own environment: "tick rank kB",
# and of the video's size so far: "tick video bytes".
python3 - "$pid" "${SOAK_PERIOD:-1}" > rss.csv <<'PY'
import os, sys, time
parent, period, start = sys.argv[1], float(sys.argv[2]), time.monotonic()
def ranks():
    for p in os.listdir("/proc"):
        try:
            if p.isdigit() and open("/proc/%s/stat" % p).read().rsplit(")", 1)[1].split()[1] == parent:
                env = open("/proc/%s/environ" % p, "rb").read().split(b"\0")
                rank = [e[21:] for e in env if e.startswith(b"OMPI_COMM_WORLD_RANK=")]
                if rank:
                    yield int(rank[0]), p
        except (OSError, IndexError):
            pass
tick = 0
while os.path.exists("/proc/" + parent):
    for rank, p in ranks():
        try:
            kb = [l.split()[1] for l in open("/proc/%s/status" % p) if l.startswith("VmRSS:")]
            if kb:
                print(tick, rank, kb[0], flush=True)
        except OSError:
            pass
    try:
        print(tick, "video", os.path.getsize("soak.mp4"), flush=True)
    except OSError:
        print(tick, "video", 0, flush=True)
    tick += 1
    time.sleep(max(0.0, start + tick * period - time.monotonic()))
PY
wait "$pid" || { cat soak.log; fail "the $FRAMES-frame run failed"; }
frames=$(ffprobe -v error -select_streams v:0 -count_frames -show_entries stream=nb_read_frames -of csv=p=0 soak.mp4)
[ "$frames" = "$FRAMES" ] || fail "soak.mp4 has $frames frames, expected $FRAMES"
python3 - rss.csv <<'PY'
import collections, sys
rss = collections.defaultdict(list)
video = {}
for line in open(sys.argv[1]):
    t, rank, value = line.split()
    if rank == "video":
        video[int(t)] = int(value)
    else:
        rss[int(rank)].append((int(t), int(value)))
final = max(video.values(), default=0)
# The first tick at which the video holds a tenth of its final size: start-up is over by then.
warm_tick = min((t for t, size in video.items() if size >= final / 10), default=0)
if len(rss) != 3:
    sys.exit("FAIL: RSS sampled for ranks %s, expected 0-2" % sorted(rss))
worst = []
for rank, samples in sorted(rss.items()):
    n = len(samples)
    if n < 8:
        sys.exit("FAIL: rank %d: only %d samples (the run must last at least 8 sample periods)" % (rank, n))
    warm = max(3, n // 5, sum(1 for t, _ in samples if t < warm_tick))
    if warm + 4 > n:
        sys.exit("FAIL: rank %d: %d samples, the warm-up takes %d (the run must last longer)" % (rank, n, warm))
    base = max(kb for _, kb in samples[warm - 2:warm + 1])  # the level the warm-up reached
    # Up to 3 samples before the end: the close is no steady state (rank 0 remuxes the whole film to
    # faststart there, its index in memory: +2.7 MB for 3,600 frames).
    peak = max(kb for _, kb in samples[warm:n - 3])
    growth = (peak - base) / base
    worst.append(growth)
    print("soak: rank %d: %d samples, RSS %.1f MB after warm-up (sample %d), peak %.1f MB later: %+.1f%%"
          % (rank, n, base / 1024, samples[warm][0], peak / 1024, 100 * growth))
    if growth >= 0.05:
        sys.exit("FAIL: rank %d's RSS grew %.1f%% after warm-up (bound 5%%)" % (rank, 100 * growth))
print("soak: every rank within 5%% of its post-warm-up RSS (worst %+.1f%%)" % (100 * max(worst)))
PY
echo "soak: ok ($FRAMES frames)"
