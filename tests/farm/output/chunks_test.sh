#!/usr/bin/env bash
# Chunked encoding end to end (issue 32): the film is encoded in chunks of --chunk-frames K, each
# by a fresh encoder, and joined on rank 0 without re-encoding. For one format EXT:
#   1. the file is byte-identical at 1, 2 and 3 ranks, in pixel and in frame mode, and after a
#      --resume at another rank count and mode (frames and the video removed in between);
#   2. it decodes (ffprobe) to every frame once, with timestamps one frame apart (no gap, no
#      repeat), a key frame at each chunk's start (H.264: only there);
#   3. another K gives another valid file of the same frames;
#   4. WebM: the joined file plays to its end in headless Chromium, every frame decoded.
# Usage: chunks_test.sh RAYFARM SOURCE_DIR WORK_DIR EXT
set -euo pipefail
RAYFARM=$1 SRC=$2 WORK=$3 EXT=$4
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
BOX=/usr/share/assimp/models/glTF2/BoxTextured-glTF/BoxTextured.gltf
rm -rf "$WORK" && mkdir -p "$WORK"
cd "$WORK"
fail() { echo "FAIL: $*" >&2; exit 1; }
mpi() { local np=$1; shift; mpirun --oversubscribe -np "$np" "$RAYFARM" "$@"; }

# 11 frames in chunks of 4, 4 and 3; transparent where the format carries alpha.
alpha=()
case "$EXT" in webm | mov | gif) alpha=(--background transparent) ;; esac
base=(render "$BOX" --size 96x72 --frames 0:10 --spp 1 "${alpha[@]}")
args=("${base[@]}" --chunk-frames 4)
frames=11

ref=""
for np in 1 2 3; do
    for mode in pixel frame; do
        out=r${np}_$mode
        mpi "$np" "${args[@]}" --mode "$mode" -o "$out.$EXT" --stats "$out.json" 2> "$out.log" || { cat "$out.log"; fail "np $np $mode failed"; }
        if [ -z "$ref" ]; then ref=$out; continue; fi
        cmp -s "$ref.$EXT" "$out.$EXT" || fail "np $np $mode: $out.$EXT differs from $ref.$EXT"
    done
done
echo "chunks $EXT: 1-3 ranks x pixel/frame: byte-identical ($(stat -c %s "$ref.$EXT") bytes)"

# Resume at another rank count and mode, from a run missing frames and its video.
rm "r3_frame.$EXT" r3_frame.$EXT.frames/frame_000001.png r3_frame.$EXT.frames/frame_000005.png r3_frame.$EXT.frames/frame_000010.png
mpi 2 "${args[@]}" --mode pixel -o "r3_frame.$EXT" --resume 2> resume.log || { cat resume.log; fail "resume failed"; }
grep -q "8 of 11 frames kept in r3_frame.$EXT.frames, 3 to render" resume.log || { cat resume.log; fail "resume did not render exactly the 3 missing frames"; }
cmp -s "$ref.$EXT" "r3_frame.$EXT" || fail "resumed at np 2 pixel: differs from $ref.$EXT"
rm "r3_frame.$EXT" r3_frame.$EXT.frames/frame_000004.png r3_frame.$EXT.frames/frame_000006.png
mpi 3 "${args[@]}" --mode frame -o "r3_frame.$EXT" --resume 2> resume2.log || { cat resume2.log; fail "second resume failed"; }
grep -q "9 of 11 frames kept in r3_frame.$EXT.frames, 2 to render" resume2.log || { cat resume2.log; fail "second resume did not render exactly 2"; }
cmp -s "$ref.$EXT" "r3_frame.$EXT" || fail "resumed at np 3 frame: differs from $ref.$EXT"
echo "chunks $EXT: --resume at np 2 pixel and np 3 frame: byte-identical"

# Decoded: every frame once, one frame apart, key frames where chunks start (a GIF: the count).
check_joins() {  # file K
    local file=$1 k=$2 n
    n=$(ffprobe -v error -select_streams v:0 -count_frames -show_entries stream=nb_read_frames -of csv=p=0 "$file")
    [ "$n" = "$frames" ] || fail "$file decodes to $n frames, expected $frames"
    [ "$EXT" = gif ] && return 0
    ffprobe -v error -select_streams v:0 -show_entries packet=pts,flags -of csv=p=0 "$file" > "$file.packets"
    python3 - "$file.packets" "$k" "$frames" "$EXT" <<'PY' || fail "$file: packet timestamps or key frames wrong"
import sys
rows = [l.strip().split(",") for l in open(sys.argv[1]) if l.strip()]
k, n, ext = int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
pts = sorted(int(r[0]) for r in rows)
steps = [b - a for a, b in zip(pts, pts[1:])]
step = steps[0]
# One frame apart: equal steps, within one tick where the clock does not divide the rate (WebM: ms).
ok = len(rows) == n and min(steps) > 0 and max(steps) - min(steps) <= 1
by_pts = {int(r[0]): "K" in r[1] for r in rows}
for i, p in enumerate(pts):
    if i % k == 0 and not by_pts[p]:
        ok = False; print("frame %d starts a chunk but is no key frame" % i)
    if ext == "mp4" and i % k != 0 and by_pts[p]:
        ok = False; print("frame %d is a key frame inside a chunk" % i)
print("%d packets, pts step %d, key frames at %s" % (len(rows), step, [i for i, p in enumerate(pts) if by_pts[p]]))
sys.exit(not ok)
PY
}
check_joins "$ref.$EXT" 4
mpi 1 "${base[@]}" --chunk-frames 3 --mode pixel --no-frames -o "k3.$EXT" 2> k3.log || { cat k3.log; fail "K=3 run failed"; }
check_joins "k3.$EXT" 3
case "$EXT" in
    # Inter-coded: another K puts key frames elsewhere, so another file.
    mp4 | webm) cmp -s "$ref.$EXT" "k3.$EXT" && fail "K=3 gave the same file as K=4: the chunk length has no effect" ;;
    # ProRes codes every frame alone, and a GIF is made whole on rank 0: K changes nothing.
    mov | gif) cmp -s "$ref.$EXT" "k3.$EXT" || fail "K=3 gave another $EXT than K=4, though K cannot matter to it" ;;
esac
echo "chunks $EXT: decodes to $frames frames one frame apart, a key frame at each chunk start; K=3 valid too"

if [ "$EXT" = webm ]; then
    command -v chromium > /dev/null || fail "chromium missing (Debian package chromium; tests/install-deps.sh)"
    cat > play.html <<HTML
<!doctype html><title>loading</title>
<video id=v muted src="$ref.$EXT"></video>
<script>
const v = document.getElementById('v');
// Reported once the video has ended, from the event or (under headless virtual time the
// event can come late) from a look every 100 ms.
function report() {
  if (!v.ended || document.title.startsWith('ended')) return;
  const q = v.getVideoPlaybackQuality();
  document.title = 'ended frames=' + q.totalVideoFrames + ' dropped=' + q.droppedVideoFrames + ' duration=' + v.duration.toFixed(3);
}
v.addEventListener('ended', report);
setInterval(report, 100);
v.addEventListener('error', () => { document.title = 'error ' + (v.error && v.error.code); });
v.play();
</script>
HTML
    # Waited for in real time through the DevTools protocol: under --virtual-time-budget,
    # Chromium 156 dumped the page before its media pipeline had loaded the file (title still
    # "loading") in most runs.
    title=$(python3 "$SRC/tests/farm/output/chromium_title.py" "file://$WORK/play.html" --timeout 90 \
        --autoplay-policy=no-user-gesture-required 2> chromium.log) || { cat chromium.log; fail "Chromium did not end the joined WebM: '$title'"; }
    case "$title" in "ended frames=$frames "*) ;; *) fail "Chromium played the joined WebM to: '$title' (expected ended frames=$frames)" ;; esac
    echo "chunks webm: Chromium played the joined file to its end: $title"
fi
