#!/usr/bin/env bash
# Issue 30: nothing lost, nothing misleading. Real processes on the real binary, each outcome
# decoded back with ffprobe/ffmpeg and, where a run was cut short, resumed and compared with a
# run never interrupted.
#   lock    two renders on one -o: the second refuses at once naming the first's host and pid;
#           the first's video has every frame and its manifest lists each frame once
#   stale   kill -9 leaves a lock: the next run takes it over; another host's lock is refused
#   hup     kill -HUP: frames kept, the GIF written, the resume line; --resume = uninterrupted
#   hup-mpi SIGHUP to mpirun's whole process group (np 3): the same under the farm
#   pipe    render 2>&1 | head -1: exit 141, the resume line in the frames log and the stats file
#   xfsz    ulimit -f: still leaves no partial PNG, render says what the full-disk path says
#   paths   outputs that are inputs, each other or the frames directory; still's extensions
#   rerun   a second run over kept frames refuses, offering --resume and --overwrite
# Usage: output_guard_test.sh RAYFARM SOURCE_DIR WORK_DIR CASE
set -euo pipefail
RAYFARM=$1 SRC=$2 WORK=$3 CASE=$4
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
SCENE=$SRC/scenes/flight.json
BOX=/usr/share/assimp/models/glTF2/BoxTextured-glTF
rm -rf "$WORK"
mkdir -p "$WORK"
cd "$WORK"

fail() { echo "FAIL: $*" >&2; exit 1; }
frames_of() { ffprobe -v error -select_streams v:0 -count_frames -show_entries stream=nb_read_frames -of csv=p=0 "$1"; }
decoded() { ffmpeg -v error -i "$1" -f framemd5 -pix_fmt rgba - | grep -v '^#' | awk -F, '{print $NF}'; }
wait_for_pngs() {  # dir count timeout-seconds
    local t=0
    while [ "$(ls "$1" 2>/dev/null | grep -c '^frame_.*\.png$')" -lt "$2" ]; do
        sleep 0.1; t=$((t + 1)); [ $t -lt $(($3 * 10)) ] || fail "fewer than $2 frames in $1 after $3 s"
    done
}
# The interrupted line's span: "holds frames 0–N of 0–59" ("frame 0" for one), and while the encoder still drains
# "… so far, 0–M once its encoder finishes" (the video then holds M + 1 frames if the close
# finishes before mpirun's SIGKILL, N + 1 if not).
HOLDS='holds (frame 0|frames 0–[0-9]+) of 0–59( so far, 0(–[0-9]+)? once its encoder finishes)? \(playable\)'
# Checks that VIDEO plays the frames LOG's last interrupted line says it holds.
check_held() {  # log video
    local line now later played
    line=$(grep -E "$HOLDS" "$1" | tail -1)
    now=$(printf '%s\n' "$line" | sed -nE 's/.*holds frames 0–([0-9]+) of.*/\1/p; s/.*holds frame 0 of.*/0/p')
    later=$(printf '%s\n' "$line" | sed -nE 's/.* so far, 0–([0-9]+) once its encoder finishes.*/\1/p; s/.* so far, 0 once its encoder finishes.*/0/p')
    played=$(frames_of "$2")
    [ -n "$now" ] || { cat "$1"; fail "$1: no interrupted line with the video's frames"; }
    [ "$played" = $((now + 1)) ] || { [ -n "$later" ] && [ "$played" = $((later + 1)) ]; } ||
        fail "$2 plays $played frames, the line says: $line"
    held=$((played - 1))
}
# A usage error: exactly one line "rayfarm: error: ...PATTERN..." and exit status 2.
expect_refusal() {  # pattern command...
    local pattern=$1 err status
    shift
    set +e
    err=$("$@" 2>&1 >/dev/null)
    status=$?
    set -e
    [ "$status" -eq 2 ] || fail "$*: exit status $status, expected 2 ($err)"
    [ "$(printf '%s\n' "$err" | wc -l)" -eq 1 ] || fail "$*: expected one error line, got: $err"
    case "$err" in "rayfarm: error: "*"$pattern"*) ;; *) fail "$*: unexpected message: $err" ;; esac
}
# The frames directory's checksum list names each frame once, and every PNG matches it.
manifest_consistent() {  # dir frames
    local lines names
    lines=$(wc -l < "$1/rayfarm-frames.sha256")
    names=$(awk '{print $2}' "$1/rayfarm-frames.sha256" | sort -u | wc -l)
    [ "$lines" = "$2" ] && [ "$names" = "$2" ] || fail "$1: $lines checksum lines for $names names, expected $2"
    (cd "$1" && sha256sum --quiet -c rayfarm-frames.sha256) || fail "$1: a frame does not match its checksum"
}

# Long enough to be caught mid-run (about 10 s on two cores), short enough for the suite.
slow=(render "$SCENE" --size 128x72 --spp 64 --frames 0:59)

case "$CASE" in
lock)
    "$RAYFARM" "${slow[@]}" -o same.mp4 2> a.log &
    a=$!
    wait_for_pngs same.mp4.frames 2 60
    start=$(date +%s.%N)
    # The issue's race: a second render at 1 spp on the same output, and one on another video
    # that shares the frames directory.
    expect_refusal "same.mp4: another render is writing it (pid $a on $(hostname) since" \
        "$RAYFARM" render "$SCENE" --size 128x72 --spp 1 --frames 0:59 -o same.mp4
    expect_refusal "same.mp4.frames: another render is writing it (pid $a on $(hostname)" \
        "$RAYFARM" render "$SCENE" --size 128x72 --spp 1 --frames 0:59 -o other.mp4 --frames-dir same.mp4.frames
    took=$(python3 -c "import sys,time; print('%.2f' % (time.time() - float(sys.argv[1])))" "$start")
    python3 -c "import sys; sys.exit(float(sys.argv[1]) > 5)" "$took" || fail "the refusals took $took s"
    kill -0 "$a" 2>/dev/null || { cat a.log; fail "the first render ended before the second was refused: no race tested"; }
    wait "$a" || { cat a.log; fail "the first render failed"; }
    grep -q "^rayfarm: wrote same.mp4: 60 frames" a.log || { cat a.log; fail "no wrote line"; }
    [ "$(frames_of same.mp4)" = 60 ] || fail "same.mp4 decodes to $(frames_of same.mp4) frames, expected 60"
    ffmpeg -v error -xerror -i same.mp4 -f null - 2> dec.log && [ ! -s dec.log ] || { cat dec.log; fail "same.mp4 has decoding errors"; }
    manifest_consistent same.mp4.frames 60
    [ ! -e same.mp4.lock ] && [ ! -e same.mp4.frames.lock ] || fail "lock files left after the run"
    [ ! -e other.mp4 ] && [ ! -e other.mp4.lock ] || fail "the refused run left other.mp4 or its lock"
    # --resume accepts the frames (all of one run) and gives the same video.
    "$RAYFARM" "${slow[@]}" -o same.mp4 --resume 2> r.log || { cat r.log; fail "resume failed"; }
    grep -q "resume: 60 of 60 frames kept" r.log || { cat r.log; fail "resume did not keep all 60 frames"; }
    echo "lock: second render refused in $took s naming pid $a on $(hostname); 60 frames decode cleanly, manifest 60 lines"
    ;;
stale)
    "$RAYFARM" "${slow[@]}" -o st.mp4 2> a.log &
    a=$!
    wait_for_pngs st.mp4.frames 3 60
    kill -9 "$a"
    set +e; wait "$a"; set -e
    [ -e st.mp4.lock ] && [ -e st.mp4.frames.lock ] || fail "kill -9 left no lock to take over (nothing tested)"
    "$RAYFARM" "${slow[@]}" -o st.mp4 --resume 2> r.log || { cat r.log; fail "resume after kill -9 failed"; }
    grep -q "^rayfarm: note: st.mp4: took over the lock of pid $a on $(hostname) (no longer running)$" r.log ||
        { cat r.log; fail "no note of the stale lock taken over"; }
    [ "$(frames_of st.mp4)" = 60 ] || fail "st.mp4 decodes to $(frames_of st.mp4) frames after resume"
    manifest_consistent st.mp4.frames 60
    "$RAYFARM" "${slow[@]}" -o ref.mp4 --no-frames 2> ref.log || { cat ref.log; fail "reference run failed"; }
    cmp -s <(decoded st.mp4) <(decoded ref.mp4) || fail "killed+resumed video differs from an uninterrupted run"
    # A lock of a live-looking holder on another host cannot be judged: refused.
    printf 'rayfarm-lock farm9 4242 - - 1796400000\n' > st.mp4.lock
    expect_refusal "st.mp4: another render is writing it (pid 4242 on farm9 since" "$RAYFARM" "${slow[@]}" -o st.mp4 --resume
    [ "$(cat st.mp4.lock)" = "rayfarm-lock farm9 4242 - - 1796400000" ] || fail "another host's lock was touched"
    echo "stale: kill -9's lock taken over by --resume (video identical to an uninterrupted run); farm9's lock refused"
    ;;
hup)
    "$RAYFARM" "${slow[@]}" -o h.gif 2> h.log &
    a=$!
    wait_for_pngs h.gif.frames 3 60
    kill -HUP "$a"
    set +e; wait "$a"; rc=$?; set -e
    [ "$rc" = 129 ] || { cat h.log; fail "exit $rc after SIGHUP, expected 129"; }
    grep -Eq "^rayfarm: interrupted \(SIGHUP\): the video h\.gif $HOLDS$" h.log || { cat h.log; fail "no interrupted line"; }
    resume=$(sed -n 's/^rayfarm: to resume: //p' h.log)
    [ -n "$resume" ] || { cat h.log; fail "no resume line"; }
    grep -q "to resume: " h.gif.frames/rayfarm.log || fail "the frames log has no resume line"
    check_held h.log h.gif
    eval "$resume" 2> r.log || { cat r.log; fail "the printed resume command failed"; }
    "$RAYFARM" "${slow[@]}" -o ref.gif --no-frames 2> ref.log || { cat ref.log; fail "reference run failed"; }
    cmp -s h.gif ref.gif || fail "hung-up+resumed GIF differs from one uninterrupted run"
    echo "hup: exit 129, GIF of $((held + 1)) frames written, resumed GIF byte-identical to an uninterrupted run"
    ;;
hup-mpi)
    # A dropped ssh session: SIGHUP to the whole process group, mpirun and its 3 ranks at once.
    setsid mpirun --oversubscribe -np 3 "$RAYFARM" "${slow[@]}" -o hm.mp4 2> hm.log &
    a=$!
    wait_for_pngs hm.mp4.frames 3 60
    kill -HUP -- -"$a"
    set +e; wait "$a"; set -e
    grep -Eq "^rayfarm: interrupted \(SIG(HUP|TERM)\): the video hm\.mp4 $HOLDS$" hm.log ||
        { cat hm.log; fail "no interrupted line"; }
    grep -q "^rayfarm: to resume: mpirun .*--resume$" hm.mp4.frames/rayfarm.log || { cat hm.mp4.frames/rayfarm.log; fail "no resume line in the frames log"; }
    check_held hm.log hm.mp4
    sleep 1
    pgrep -f "rayfarm render .* -o hm.mp4" > /dev/null && fail "a rank outlived the hang-up"
    mpirun --oversubscribe -np 3 "$RAYFARM" "${slow[@]}" -o hm.mp4 --resume 2> r.log || { cat r.log; fail "resume failed"; }
    [ "$(frames_of hm.mp4)" = 60 ] || fail "resumed hm.mp4 has $(frames_of hm.mp4) frames"
    "$RAYFARM" "${slow[@]}" -o ref.mp4 --no-frames 2> ref.log || { cat ref.log; fail "reference run failed"; }
    cmp -s <(decoded hm.mp4) <(decoded ref.mp4) || fail "hung-up+resumed video differs from an uninterrupted run"
    echo "hup-mpi: the process group hung up: $((held + 1)) frames kept and playable, resume line in the frames log; resumed video identical"
    ;;
pipe)
    # Away from a terminal, progress is a line every 5 s: the film must outlast one (about 8 s
    # here unloaded), or the first write after head has gone is the closing line of a finished run.
    slow=(render "$SCENE" --size 256x144 --spp 64 --frames 0:59)
    set +e
    "$RAYFARM" "${slow[@]}" -o p.mp4 --stats p.json 2>&1 | head -1 > head.out
    rc=${PIPESTATUS[0]}
    set -e
    [ "$rc" = 141 ] || fail "exit $rc with stderr piped into head -1, expected 141"
    grep -q "^rayfarm: .*frames 0–59 of" head.out || fail "head saw: $(cat head.out)"
    grep -Eq "^rayfarm: interrupted \(SIGPIPE\): the video p\.mp4 holds (frame 0|frames 0–[0-9]+) of 0–59" p.mp4.frames/rayfarm.log ||
        { cat p.mp4.frames/rayfarm.log; fail "no interrupted line in the frames log"; }
    python3 - p.json <<'PY' || fail "stats file after the broken pipe"
import json, sys
s = json.load(open(sys.argv[1]))
assert s["interrupted"] == "SIGPIPE", s.get("interrupted")
assert s["resume"].endswith("--resume"), s.get("resume")
assert "holds frame" in s["video"], s.get("video")
PY
    check_held p.mp4.frames/rayfarm.log p.mp4
    resume=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['resume'])" p.json)
    eval "$resume" 2> r.log || { cat r.log; fail "the resume command from the stats file failed"; }
    [ "$(frames_of p.mp4)" = 60 ] || fail "resumed p.mp4 has $(frames_of p.mp4) frames"
    "$RAYFARM" "${slow[@]}" -o ref.mp4 --no-frames 2> ref.log || { cat ref.log; fail "reference run failed"; }
    cmp -s <(decoded p.mp4) <(decoded ref.mp4) || fail "piped+resumed video differs from an uninterrupted run"
    echo "pipe: exit 141, $((held + 1)) frames kept, resume line in the frames log and stats; resumed video identical"
    ;;
xfsz)
    # 8 blocks (4 KiB in bash): a 320x180 PNG of the flight scene is larger.
    printf 'old bytes\n' > keep.png
    set +e
    (ulimit -f 8; "$RAYFARM" still "$SCENE" --size 320x180 -o u.png 2> u.log; echo $? > u.rc)
    (ulimit -f 8; "$RAYFARM" still "$SCENE" --size 320x180 -o keep.png 2> keep.log)
    set -e
    [ "$(cat u.rc)" = 1 ] || { cat u.log; fail "still past ulimit -f: exit $(cat u.rc), expected 1"; }
    [ "$(cat u.log)" = "rayfarm: error: u.png: cannot write: File too large" ] || { cat u.log; fail "still past ulimit -f: message"; }
    ls u.png* keep.png.* 2>/dev/null && fail "a partial PNG was left"
    [ "$(cat keep.png)" = "old bytes" ] || fail "the file a failed still would have replaced was damaged"
    # render: the video outgrows the limit; the full-disk path's message, and the resume works.
    set +e
    (ulimit -f 40; "$RAYFARM" render "$SCENE" --size 160x90 --spp 4 -o u.mp4 2> r.log; echo $? > r.rc)
    set -e
    [ "$(cat r.rc)" = 1 ] || { cat r.log; fail "render past ulimit -f: exit $(cat r.rc), expected 1"; }
    grep -Eq "^rayfarm: error: u\.mp4: writing failed: File too large; the video u\.mp4 holds (frame 0|frames 0–[0-9]+) of 0–96; finished frames are in u\.mp4\.frames; to resume: .*--resume$" r.log ||
        { cat r.log; fail "render past ulimit -f: not the full-disk path's message"; }
    "$RAYFARM" render "$SCENE" --size 160x90 --spp 4 -o u.mp4 --resume 2> rr.log || { cat rr.log; fail "resume after EFBIG failed"; }
    [ "$(frames_of u.mp4)" = 97 ] || fail "resumed u.mp4 has $(frames_of u.mp4) frames"
    echo "xfsz: still leaves no partial PNG and keeps the old file; render stops with the file, EFBIG and the resume command"
    ;;
paths)
    cp "$SCENE" scene.json
    cp -r "$BOX" box
    sum() { sha256sum scene.json box/* | sha256sum; }
    before=$(sum)
    expect_refusal "scene.json: still writes a PNG: expected a .png" "$RAYFARM" still scene.json -o scene.json
    expect_refusal "x.mp4: still writes a PNG" "$RAYFARM" still scene.json -o x.mp4
    expect_refusal "scene.json: --stats names a file this run reads (scene.json)" "$RAYFARM" still scene.json -o s.png --stats scene.json
    expect_refusal "s.png: --stats names the same file as -o" "$RAYFARM" still scene.json -o s.png --stats s.png
    expect_refusal "box/CesiumLogoFlat.png: -o names a file this run reads" "$RAYFARM" still box/BoxTextured.gltf -o box/CesiumLogoFlat.png
    expect_refusal "box/BoxTextured0.bin: --stats names a file this run reads" \
        "$RAYFARM" still box/BoxTextured.gltf -o b.png --stats box/BoxTextured0.bin
    ln -s box/CesiumLogoFlat.png link.png
    expect_refusal "link.png: -o names a file this run reads" "$RAYFARM" still box/BoxTextured.gltf -o link.png
    r=("$RAYFARM" render scene.json --size 32x18 --frames 0:1)
    expect_refusal "a.mp4: --stats names the same file as -o (a.mp4)" "${r[@]}" -o a.mp4 --stats a.mp4
    expect_refusal "scene.json: --stats names a file this run reads" "${r[@]}" -o a.mp4 --stats scene.json
    expect_refusal "a.mp4: --frames-dir names the same file as -o" "${r[@]}" -o a.mp4 --frames-dir a.mp4
    expect_refusal "a.mp4.frames: --stats names the same file as --frames-dir" "${r[@]}" -o a.mp4 --stats a.mp4.frames
    expect_refusal "p.png: --poster names the same file as --contact-sheet" "${r[@]}" -o a.mp4 --poster p.png --contact-sheet p.png
    b=("$RAYFARM" render box/BoxTextured.gltf --size 32x24 --frames 0:1)
    expect_refusal "box/CesiumLogoFlat.png: --poster names a file this run reads" "${b[@]}" -o b.mp4 --poster box/CesiumLogoFlat.png
    expect_refusal "box/BoxTextured0.bin: --stats names a file this run reads" "${b[@]}" -o b.mp4 --stats box/BoxTextured0.bin
    # view: Ctrl+S would write the keyed path over the scene (offscreen: no display needed).
    if QT_QPA_PLATFORM=offscreen "$RAYFARM" view --help > /dev/null 2>&1; then
        expect_refusal "scene.json: -o names a file this run reads" env QT_QPA_PLATFORM=offscreen "$RAYFARM" view scene.json -o scene.json
        expect_refusal "v.json: --stats names the same file as -o" env QT_QPA_PLATFORM=offscreen "$RAYFARM" view scene.json -o v.json --stats v.json
    fi
    [ "$(sum)" = "$before" ] || fail "an input was changed"
    for f in a.mp4 a.mp4.frames b.mp4 b.mp4.frames s.png b.png x.mp4 p.png; do [ -e "$f" ] && fail "a refused run left $f"; done
    echo "paths: outputs (still, render, view) naming an input, another output or the frames directory refused before rendering; inputs intact"
    ;;
rerun)
    r=("$RAYFARM" render "$SCENE" --size 32x18 --frames 0:3)
    "${r[@]}" -o re.mp4 2> 1.log || { cat 1.log; fail "first run failed"; }
    sums=$(cd re.mp4.frames && sha256sum frame_*.png)
    expect_refusal "re.mp4.frames: holds 4 frame files of an earlier run; add --resume to render only the frames missing, or --overwrite" \
        "${r[@]}" -o re.mp4
    [ "$(cd re.mp4.frames && sha256sum frame_*.png)" = "$sums" ] || fail "the refused run touched the kept frames"
    expect_refusal "--resume and --overwrite contradict" "${r[@]}" -o re.mp4 --resume --overwrite
    "${r[@]}" -o re.mp4 --overwrite 2> 2.log || { cat 2.log; fail "--overwrite failed"; }
    [ "$(frames_of re.mp4)" = 4 ] || fail "--overwrite gave $(frames_of re.mp4) frames"
    manifest_consistent re.mp4.frames 4
    "${r[@]}" -o re.mp4 --resume 2> 3.log || { cat 3.log; fail "--resume failed"; }
    grep -q "resume: 4 of 4 frames kept" 3.log || { cat 3.log; fail "--resume did not keep the frames"; }
    echo "rerun: a second run over kept frames refused naming --resume and --overwrite; both work"
    ;;
*) fail "unknown case $CASE" ;;
esac
echo ok
