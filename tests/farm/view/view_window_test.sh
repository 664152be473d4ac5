#!/usr/bin/env bash
# rayfarm view driven for real: a window under Xvfb, mouse and keys through xdotool (XTEST),
# the picture grabbed from the X server with ImageMagick's `import`.
# Usage: [VIEW_NP=3] view_window_test.sh RAYFARM WORK_DIR CASE
# With VIEW_NP=N the window runs under `mpirun --oversubscribe -np N`: rank 0 owns the window,
# the other ranks render every frame (pixel mode); the same checks apply, and after Ctrl+Q
# mpirun itself exits 0 within 2 s and no rank or orted is left.
#   no-display   without a display: one error line naming render and still, exit 2
#   still SCENE [OPTIONS]  the window's picture at rest equals `still`'s PNG with the same
#                picture options (exact: 0 differing pixels)
#   author SCENE a drag changes the picture; K then Ctrl+S writes a scene that `render` accepts,
#                whose frame 0 equals the window exactly; Ctrl+R renders the film (runFarm on
#                the window's own ranks, no child process), Ctrl+R
#                again cancels it keeping frames, a third Ctrl+R resumes to the whole film (MP4
#                frame count checked with ffprobe); Ctrl+Q ends the process with status 0
#                within 2 s and leaves no rayfarm process; --stats has the frames shown
#   interact SCENE  middle and shift drags pan (the same pan, unlike an orbit), the wheel
#                zooms, F frames, T tints: each changes the picture, and R (or T again)
#                restores still's picture exactly; F twice from the same camera gives the same
#                picture; Right shows frame 1 exactly as still --frame 1; Space plays (the picture
#                keeps changing) and pauses; Home shows frame 0 again
#   scrub SCENE  (a scene whose camera is fixed and whose model is skinned) a mouse drag on the
#                timeline slider changes the picture to exactly one of the film's other frames
#                as `render` writes them (so the window shows the posed model of that frame),
#                whose pose differs from frame 0's; Home shows frame 0 again
#   preview SCENE  render --preview opens a window on the frames as they complete; closing it
#                mid-render leaves the render to finish (status 0, every frame); a window on the
#                finished frames directory (view --watch) shows the last frame exactly
#   film-close SCENE  Ctrl+Q while Ctrl+R renders: status 0 within 2 s, the frames done kept
#                (said on stderr) and playable in the MP4, no process left; before it, Ctrl+R
#                refuses while another render holds the film's lock
#   film-killed-rank SCENE  (VIEW_NP=3) a rank killed while Ctrl+R renders: the window stays,
#                names it in its title and a red banner; the MP4 plays the frames done
#   killed-rank SCENE  (VIEW_NP=3) rank 2 is killed while it renders: the window stays and names
#                it on stderr, in its title and in a red banner over the picture that is still
#                there 2 s later; Ctrl+Q then ends the session (mpirun exits
#                non-zero within 5 s) and leaves no process. mpirun runs with
#                --mca orte_abort_on_non_zero_status 0, so the window outlives the dead rank
#                (killed-rank-default covers mpirun's defaults).
#   killed-rank-default SCENE  (VIEW_NP=3) the same under mpirun's defaults, which end every
#                rank when one dies: rank 0 names the dead rank (by which rank fails to answer
#                mpirun's SIGTERM) in one error line, and the session is gone within 5 s; a
#                report window (a process of its own) shows it, in its title and a red banner,
#                until Ctrl+Q closes it
#   window-destroyed SCENE  the window destroyed from outside (xdotool windowclose: XDestroyWindow,
#                as a crashed compositor or a killed X forwarder does): the session ends within
#                5 s with one error line saying so and status 1 (under mpirun: mpirun's status is
#                not 0), and no process of it is left
#   display-lost SCENE  the X server killed under the window: the same, naming the lost display
# Exit 77 (ctest SKIP) only when this rayfarm was built without Qt 6 (no viewer to test).
set -uo pipefail
RAYFARM=$1 WORK=$2 CASE=$3
shift 3
SIZE=160x90
W=160 H=90
mkdir -p "$WORK"
cd "$WORK" || exit 1
fail() { echo "FAIL: $*" >&2; exit 1; }

if ! help=$("$RAYFARM" view --help 2>&1); then
    case "$help" in
        *"built without Qt 6"*) echo "SKIP: $help"; exit 77 ;;
        *) fail "rayfarm view --help: $help" ;;
    esac
fi

if [ "$CASE" = no-display ]; then
    err=$(env -u DISPLAY -u WAYLAND_DISPLAY -u QT_QPA_PLATFORM "$RAYFARM" view "$@" 2>&1)
    status=$?
    [ $status -eq 2 ] || fail "exit status $status, expected 2"
    [ "$(printf '%s\n' "$err" | wc -l)" -eq 1 ] || fail "expected one line, got: $err"
    case "$err" in
        "rayfarm: error: view: "*render*still*) echo "ok: $err"; exit 0 ;;
        *) fail "unexpected message: $err" ;;
    esac
fi

for tool in Xvfb xdotool import compare ffprobe; do
    command -v $tool >/dev/null || fail "$tool missing (tests/install-deps.sh installs it)"
done

# A private X server on a display number of its own, waited for until it answers a client.
# The number is chosen here, away from the low ones desktops and other tools take, and skipped
# when a lock or socket of it exists: Xvfb's own pick (-displayfd) once landed on a number whose
# socket another server still held ("server already running"), and the window then failed to
# connect. The server is ours when it reports our odd screen size. Up to ten attempts.
export HWLOC_COMPONENTS=-gl  # Open MPI's hwloc must not open X displays of its own
XVFB=
VIEW=
cleanup() {
    [ -n "$VIEW" ] && kill "$VIEW" 2>/dev/null
    [ -n "$XVFB" ] && kill "$XVFB" 2>/dev/null
    wait 2>/dev/null
}
trap cleanup EXIT
start_xvfb() {
    local n=$((200 + $$ % 700)) attempt
    for attempt in $(seq 10); do
        while [ -e /tmp/.X$n-lock ] || [ -e /tmp/.X11-unix/X$n ]; do n=$((n + 1)); done
        Xvfb :$n -screen 0 1280x801x24 -nolisten tcp 2>xvfb.log &
        XVFB=$!
        export DISPLAY=:$n
        for _ in $(seq 100); do
            if [ "$(xdotool getdisplaygeometry 2>/dev/null)" = "1280 801" ] &&
                ! grep -q "server already running\|CreateListener() failed" xvfb.log; then
                echo "$n" >display.txt
                return 0
            fi
            kill -0 $XVFB 2>/dev/null || break
            sleep 0.1
        done
        echo "note: Xvfb on :$n did not answer as ours (attempt $attempt): $(tail -2 xvfb.log)" >&2
        kill $XVFB 2>/dev/null
        wait $XVFB 2>/dev/null
        XVFB=
        n=$((n + 1))
    done
    fail "Xvfb did not start: $(cat xvfb.log)"
}
start_xvfb

LAUNCH=()
if [ -n "${VIEW_NP:-}" ]; then
    export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
    LAUNCH=(mpirun --oversubscribe -np "$VIEW_NP")
fi

alive() {  # a running process, not a zombie waiting to be reaped
    local st
    st=$(ps -o stat= -p "$1" 2>/dev/null) || return 1
    case "$st" in Z*) return 1 ;; *) return 0 ;; esac
}

descendants() {  # every process below $1 (ranks, orted), one pid per line
    local c
    for c in $(pgrep -P "$1"); do echo "$c"; descendants "$c"; done
}

start_view() {  # args for rayfarm view; sets VIEW (the process, or mpirun) and WID
    local try
    for try in 1 2; do
        "${LAUNCH[@]}" "$RAYFARM" view "$@" >view.log 2>&1 &
        VIEW=$!
        WID=
        for _ in $(seq 100); do
            # Only once it is mapped: focusing a window found but not yet viewable fails with
            # BadMatch (X_SetInputFocus), and xdotool then sends no key (seen in CI under load).
            WID=$(xdotool search --onlyvisible --name '^rayfarm (view|preview)' 2>/dev/null | head -1)
            [ -n "$WID" ] && return 0
            kill -0 $VIEW 2>/dev/null || break
            sleep 0.2
        done
        # Once: a window that could not connect to a server that answered a moment ago is the
        # display's trouble, not the viewer's (seen under load with other sessions' servers).
        if [ $try = 1 ] && ! kill -0 $VIEW 2>/dev/null && grep -q "cannot open a window" view.log; then
            wait $VIEW 2>/dev/null
            echo "note: the window could not connect to $DISPLAY ($(xdotool getdisplaygeometry 2>&1 | head -1)); once more" >&2
            xdotool getdisplaygeometry >/dev/null 2>&1 || { kill $XVFB 2>/dev/null; wait $XVFB 2>/dev/null; start_xvfb; }
            continue
        fi
        break
    done
    kill -0 $VIEW 2>/dev/null || fail "view exited early: $(cat view.log)"
    fail "no window appeared: $(cat view.log)"
}

close_view() {  # Ctrl+Q, then waits up to $1 s for the process (or mpirun) to end; sets STATUS
    local what=$2
    xdotool windowfocus --sync "$WID" key ctrl+q
    for _ in $(seq $(($1 * 20))); do kill -0 $VIEW 2>/dev/null || break; sleep 0.05; done
    kill -0 $VIEW 2>/dev/null && fail "$what still running $1 s after Ctrl+Q"
    wait $VIEW
    STATUS=$?
    VIEW=
}

grab() {  # the picture area, top-left W×H of the window, as $1
    import -window "$WID" png:- 2>/dev/null | convert png:- -crop ${W}x${H}+0+0 +repage "$1"
}

# The lasting report of a stopped farm: the window's title names it, and the red banner
# (#c00000) covers the picture's top-left corner. $1: text the title must contain.
check_stopped_banner() {
    local title px
    title=$(xdotool getwindowname "$WID" 2>/dev/null)
    case "$title" in *"stopped: "*"$1"*) ;; *) fail "the window title does not report it: '$title'" ;; esac
    grab stopped.png
    px=$(convert stopped.png -format '%[fx:int(255*p{2,2}.r)],%[fx:int(255*p{2,2}.g)],%[fx:int(255*p{2,2}.b)]' info:)
    [ "$px" = "192,0,0" ] || fail "no red banner over the picture (pixel 2,2 is $px; see $WORK/stopped.png)"
}

differing() {  # pixels that differ between two images (ImageMagick AE, exact)
    compare -metric AE "$1" "$2" null: 2>&1 | cut -d' ' -f1
}

# Waits up to $2 s for the window to show exactly the picture in $1; on timeout writes
# $3.grab.png and $3.diff.png and fails.
wait_equal() {
    local ref=$1 secs=$2 name=$3 n=
    for _ in $(seq $((secs * 4))); do
        grab "$name.grab.png"
        n=$(differing "$name.grab.png" "$ref")
        [ "$n" = 0 ] && return 0
        sleep 0.25
    done
    compare "$name.grab.png" "$ref" "$name.diff.png" 2>/dev/null
    fail "$name: window differs from $ref in $n pixels after ${secs} s (see $WORK/$name.diff.png)"
}

# Orbit: a left drag across the picture; true once the window differs from $1 (within 10 s).
drag_changes() {
    xdotool mousemove --window "$WID" 40 45 mousedown 1
    for i in $(seq 12); do xdotool mousemove --window "$WID" $((40 + 5 * i)) $((45 + i)); sleep 0.03; done
    xdotool mouseup 1
    for _ in $(seq 40); do
        grab moved.png
        [ "$(differing moved.png "$1")" != 0 ] && return 0
        sleep 0.25
    done
    return 1
}

psnr() {  # PSNR in dB between two images (ImageMagick; "inf" reads as a large number)
    compare -metric PSNR "$1" "$2" null: 2>&1 | cut -d' ' -f1 | sed 's/^inf$/999/'
}

# Grabs until two grabs 0.5 s apart are equal (the picture at rest), as $1.png.
settle() {
    grab "$1.png"
    for _ in $(seq 60); do
        sleep 0.5
        grab "$1.next.png"
        [ "$(differing "$1.next.png" "$1.png")" = 0 ] && return 0
        mv "$1.next.png" "$1.png"
    done
    fail "$1: the picture did not come to rest in 30 s"
}

# drag BUTTON MODIFIER NAME: a drag across the picture with BUTTON (1 left, 2 middle) and
# MODIFIER held ("" for none); the picture at rest afterwards is NAME.png; then R.
drag() {
    xdotool windowfocus --sync "$WID"
    [ -n "$2" ] && xdotool keydown "$2"
    xdotool mousemove --window "$WID" 40 45 mousedown "$1"
    for i in $(seq 12); do xdotool mousemove --window "$WID" $((40 + 5 * i)) $((45 + i)); sleep 0.03; done
    xdotool mouseup "$1"
    [ -n "$2" ] && xdotool keyup "$2"
    settle "$3"
    xdotool key r
}

scene=$1
shift
case "$CASE" in
still)
    # Any picture options after the scene go to both (--environment, --exposure, --tonemap ...).
    "$RAYFARM" still "$scene" --size $SIZE --spp 4 "$@" -o still.png 2>/dev/null || fail "still $*"
    start_view "$scene" --size $SIZE --spp 4 "$@"
    wait_equal still.png 60 rest
    echo "ok: window equals still.png ($SIZE, 4 spp${*:+, $*})"
    ;;
film-close)
    # Ctrl+Q while Ctrl+R renders: the window closes within 2 s with status 0, says how many
    # frames it kept, the MP4 plays those frames, and nothing of the session is left.
    rm -rf film.mp4.frames film.mp4 film.mp4.lock
    start_view "$scene" --size $SIZE --spp 16 -o "$PWD/film.json"
    # Issue 30 #1: a render holding the film's lock (this shell, alive) makes Ctrl+R refuse.
    printf 'rayfarm-lock %s %s - %s 1796400000\n' "$(hostname)" $$ "$(cat /proc/sys/kernel/random/boot_id)" > film.mp4.lock
    xdotool windowfocus --sync "$WID" key ctrl+r
    for _ in $(seq 100); do grep -q "render failed: .*film.mp4: another render is writing it (pid $$ on" view.log && break; sleep 0.05; done
    grep -q "render failed: .*film.mp4: another render is writing it (pid $$ on" view.log ||
        fail "Ctrl+R did not refuse a film another render holds: $(tail -3 view.log)"
    [ -e film.mp4.frames ] && fail "the refused film made its frames directory"
    rm film.mp4.lock
    xdotool windowfocus --sync "$WID" key ctrl+r
    for _ in $(seq 400); do [ -n "$(ls film.mp4.frames/frame_*.png 2>/dev/null)" ] && break; sleep 0.05; done
    [ -n "$(ls film.mp4.frames/frame_*.png 2>/dev/null)" ] || fail "the film wrote no frame: $(tail -3 view.log)"
    ours=$(descendants $VIEW)
    close_view 2 view
    [ $STATUS -eq 0 ] || fail "view exited with status $STATUS: $(cat view.log)"
    kept=$(ls film.mp4.frames/frame_*.png | wc -l)
    grep -q "rayfarm: view: render cancelled by closing the window: $kept frames kept in" view.log ||
        fail "no line saying the $kept frames are kept: $(tail -3 view.log)"
    n=$(ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=nb_read_frames -of csv=p=0 film.mp4)
    [ -n "$n" ] && [ "$n" -ge 1 ] && [ "$n" -le "$kept" ] || fail "the MP4 holds '$n' frames for $kept kept"
    sleep 1
    for pid in $ours; do
        alive "$pid" && fail "process $pid of the session left behind: $(ps -o pid=,stat=,args= -p "$pid")"
    done
    echo "ok: closed mid-film with status 0 within 2 s; $kept frames kept, the MP4 plays $n"
    ;;
film-killed-rank)
    # (VIEW_NP=3, a dead rank does not end mpirun) a rank killed while Ctrl+R renders: the
    # window stays and reports it in its title and a red banner; the MP4 plays the frames
    # done; Ctrl+Q ends the session (non-zero) and leaves no process.
    [ -n "${VIEW_NP:-}" ] || fail "film-killed-rank runs under mpirun (VIEW_NP=3)"
    LAUNCH=(mpirun --mca orte_abort_on_non_zero_status 0 --oversubscribe -np "$VIEW_NP")
    rm -rf film.mp4.frames film.mp4
    start_view "$scene" --size 320x180 --spp 64 -o "$PWD/film.json"
    xdotool windowfocus --sync "$WID" key ctrl+r
    for _ in $(seq 400); do [ -n "$(ls film.mp4.frames/frame_*.png 2>/dev/null)" ] && break; sleep 0.05; done
    [ -n "$(ls film.mp4.frames/frame_*.png 2>/dev/null)" ] || fail "the film wrote no frame: $(tail -3 view.log)"
    victim=
    for pid in $(descendants $VIEW); do [ "$(ps -o comm= -p "$pid")" = rayfarm ] && victim=$pid; done
    rank=$(tr '\0' '\n' </proc/"$victim"/environ | sed -n 's/^OMPI_COMM_WORLD_RANK=//p')
    [ -n "$rank" ] && [ "$rank" != 0 ] || fail "process $victim is not a worker rank (rank '$rank')"
    ours=$(descendants $VIEW)
    kill -9 "$victim"
    for _ in $(seq 120); do grep -q "rayfarm: error: view: render stopped: rank $rank" view.log && break; sleep 0.25; done
    grep -q "rayfarm: error: view: render stopped: rank $rank" view.log || fail "no line naming rank $rank: $(cat view.log)"
    kill -0 $VIEW 2>/dev/null || fail "the session ended with the rank, the window could not tell"
    check_stopped_banner "rank $rank"
    n=$(ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=nb_read_frames -of csv=p=0 film.mp4)
    [ -n "$n" ] && [ "$n" -ge 1 ] || fail "the MP4 of the stopped film does not play: '$n' frames"
    close_view 5 mpirun
    [ $STATUS -ne 0 ] || fail "a session that lost a rank exited 0"
    sleep 1
    for pid in $ours; do
        alive "$pid" && fail "process $pid of the session left behind: $(ps -o pid=,stat=,args= -p "$pid")"
    done
    echo "ok: $(grep 'render stopped' view.log | head -1); the MP4 plays $n frames; closed with status $STATUS"
    ;;
author)
    # 64 spp: the film rendered below (31 frames at 160x90) must last longer than the key that
    # cancels it takes to arrive; at 4 spp two ranks finished it in about 0.2 s, before the key.
    "$RAYFARM" still "$scene" --size $SIZE --spp 64 -o still.png 2>/dev/null || fail "still"
    rm -f saved.json stats.json
    start_view "$scene" --size $SIZE --spp 64 -o "$PWD/saved.json" --stats "$PWD/stats.json"
    wait_equal still.png 60 start
    drag_changes still.png || fail "a left drag did not change the picture"
    # Key the new camera at t = 0 and save.
    xdotool windowfocus --sync "$WID" key k
    sleep 0.3
    xdotool key ctrl+s
    for _ in $(seq 40); do [ -s saved.json ] && break; sleep 0.25; done
    [ -s saved.json ] || fail "Ctrl+S wrote no scene: $(cat view.log)"
    rm -rf saved.mp4.frames saved.mp4 last.mp4.frames last.mp4  # an earlier run's: render refuses to drop kept frames
    "$RAYFARM" render saved.json -o saved.mp4 --frames 0:0 --frames-dir saved.mp4.frames 2>render.log ||
        fail "render does not accept the saved scene: $(tail -1 render.log)"
    [ "$(differing saved.mp4.frames/frame_000000.png still.png)" != 0 ] || fail "the saved camera is the start camera"
    wait_equal saved.mp4.frames/frame_000000.png 60 keyed
    # Render the film from the window (Ctrl+R), cancel it after a frame, render again: it
    # resumes from the kept frames and the MP4 holds the whole film.
    cp saved.mp4.frames/frame_000000.png cli0.png
    rm -rf saved.mp4.frames saved.mp4
    frames=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['timeline']['frames'])" saved.json)
    xdotool windowfocus --sync "$WID" key ctrl+r
    for _ in $(seq 240); do [ -n "$(ls saved.mp4.frames/frame_*.png 2>/dev/null)" ] && break; sleep 0.05; done
    # The film goes through runFarm on the window's own ranks, not through a child process.
    # Only the window's own process tree counts: other tests may run `rayfarm render` meanwhile.
    for pid in $(descendants "$VIEW"); do
        ps -o args= -p "$pid" | grep -q "$RAYFARM render" && fail "the Render action started a child render: $(ps -o args= -p "$pid")"
    done
    np=${VIEW_NP:-1}
    grep -q "rayfarm: view: rendering .* through the farm ($np rank" view.log || fail "no film through the farm on $np rank(s): $(tail -3 view.log)"
    xdotool key ctrl+r
    for _ in $(seq 100); do grep -q "rayfarm: view: render cancelled" view.log && break; sleep 0.1; done
    grep -q "rayfarm: view: render cancelled" view.log || fail "no cancelled render: $(tail -3 view.log)"
    kept=$(ls saved.mp4.frames/frame_*.png | wc -l)
    [ "$kept" -ge 1 ] && [ "$kept" -lt "$frames" ] || fail "cancel kept $kept of $frames frames"
    xdotool key ctrl+r
    for _ in $(seq 600); do grep -q "rayfarm: view: rendered" view.log && break; sleep 0.1; done
    grep -q "rayfarm: resume: $kept of $frames frames kept" view.log || fail "the second render did not resume: $(tail -4 view.log)"
    grep -q "rayfarm: view: rendered" view.log || fail "the resumed render did not finish: $(tail -3 view.log)"
    n=$(ffprobe -v error -count_frames -select_streams v:0 -show_entries stream=nb_read_frames -of csv=p=0 saved.mp4)
    [ "$n" = "$frames" ] || fail "the rendered MP4 holds $n frames, the film $frames"
    # The window's film is render's film: its first (kept) and last (resumed) frames equal the
    # command line's, pixel for pixel.
    last=$(printf 'frame_%06d.png' $((frames - 1)))
    "$RAYFARM" render saved.json -o last.mp4 --frames $((frames - 1)):$((frames - 1)) --frames-dir last.mp4.frames 2>render.log ||
        fail "render of the last frame: $(tail -1 render.log)"
    [ "$(differing saved.mp4.frames/frame_000000.png cli0.png)" = 0 ] || fail "the window's film frame 0 differs from render's"
    [ "$(differing saved.mp4.frames/$last last.mp4.frames/$last)" = 0 ] || fail "the window's film $last differs from render's"
    # After the film the ranks serve the window again: a drag changes the picture.
    grab before_drag.png
    drag_changes before_drag.png || fail "a drag after the film render did not change the picture"
    # Close: the process ends with status 0 within 2 s and leaves nothing behind.
    ours=$(descendants $VIEW)
    close_view 2 view
    [ $STATUS -eq 0 ] || fail "view exited with status $STATUS: $(cat view.log)"
    pgrep -f "$RAYFARM view .*$PWD/saved.json" >/dev/null && fail "a rayfarm view process is left: $(pgrep -af "$RAYFARM view")"
    for pid in $ours; do
        alive "$pid" && fail "process $pid of the session left behind: $(ps -o pid=,stat=,args= -p "$pid")"
    done
    if [ -n "${VIEW_NP:-}" ]; then
        grep -q "\"ranks\": $VIEW_NP" stats.json || fail "stats.json does not count $VIEW_NP ranks: $(cat stats.json)"
    fi
    python3 - stats.json <<'PY' || fail "stats.json"
import json, sys
s = json.load(open(sys.argv[1]))
assert s["frames_shown"] >= 3, s
assert s["moving_frames"] >= 1 and s["latency_samples"] >= 1, s
assert 0 < s["latency_mean_ms"] <= s["latency_p95_ms"], s
PY
    echo "ok: drag, K, Ctrl+S, render frame 0 = window, Render/cancel/resume ($kept kept) to $frames frames, closed with status 0 within 2 s"
    ;;
preview)
    rm -rf pv.mp4 pv.mp4.frames
    "${LAUNCH[@]}" "$RAYFARM" render "$scene" -o "$PWD/pv.mp4" --size $SIZE --spp 36 --preview >render.log 2>&1 &
    RENDER=$!
    WID=
    for _ in $(seq 150); do
        WID=$(xdotool search --name '^rayfarm preview' 2>/dev/null | head -1)
        [ -n "$WID" ] && break
        sleep 0.2
    done
    [ -n "$WID" ] || fail "render --preview opened no window: $(cat render.log)"
    for _ in $(seq 100); do [ -n "$(ls pv.mp4.frames/frame_*.png 2>/dev/null)" ] && break; sleep 0.1; done
    kill -0 $RENDER 2>/dev/null || fail "the render ended before the preview could be closed mid-way; make it longer"
    xdotool windowfocus --sync "$WID" key ctrl+q
    for _ in $(seq 40); do xdotool search --name '^rayfarm preview' >/dev/null 2>&1 || break; sleep 0.1; done
    xdotool search --name '^rayfarm preview' >/dev/null 2>&1 && fail "the preview window did not close"
    kill -0 $RENDER 2>/dev/null || fail "closing the preview ended the render too early"
    wait $RENDER
    status=$?
    [ $status -eq 0 ] || fail "render exited $status after the preview closed: $(tail -2 render.log)"
    frames=$(ls pv.mp4.frames/frame_*.png | wc -l)
    grep -q "wrote $PWD/pv.mp4: $frames frames" render.log || fail "the render did not write every frame: $(tail -1 render.log)"
    # A window on the finished directory shows its last frame, 1:1.
    LAUNCH=()  # the watching window is a plain process, never a member of an MPI job
    start_view --watch "$PWD/pv.mp4.frames" --total "$frames"
    last=$(ls pv.mp4.frames/frame_*.png | tail -1)
    wait_equal "$last" 30 watch
    close_view 2 "view --watch"
    [ $STATUS -eq 0 ] || fail "view --watch exited $STATUS"
    echo "ok: preview closed mid-render, render finished $frames frames; --watch shows $(basename "$last") exactly"
    ;;
killed-rank)
    [ -n "${VIEW_NP:-}" ] || fail "killed-rank runs under mpirun (VIEW_NP=3)"
    LAUNCH=(mpirun --mca orte_abort_on_non_zero_status 0 --oversubscribe -np "$VIEW_NP")
    start_view "$scene" --size 320x180 --spp 1024  # seconds of work for the ranks at rest
    sleep 1
    victim=
    for pid in $(descendants $VIEW); do
        [ "$(ps -o comm= -p "$pid")" = rayfarm ] && victim=$pid  # the last rank started
    done
    [ -n "$victim" ] || fail "no rank found under mpirun"
    ours=$(descendants $VIEW)
    kill -9 "$victim"
    for _ in $(seq 60); do grep -q "rayfarm: error: view: rank [12] stopped answering" view.log && break; sleep 0.25; done
    grep -q "rayfarm: error: view: rank [12] stopped answering" view.log || fail "no line naming the lost rank: $(cat view.log)"
    kill -0 $VIEW 2>/dev/null || fail "the session ended with the rank, the window could not tell"
    lost=$(sed -n 's/^rayfarm: error: view: rank \([12]\) stopped answering.*/\1/p' view.log | head -1)
    sleep 2  # it lasts: not a status line that the next frame overwrites
    check_stopped_banner "rank $lost stopped answering"
    close_view 5 mpirun
    [ $STATUS -ne 0 ] || fail "a session that lost a rank exited 0"
    sleep 1  # the killed rank and mpirun's helpers are reaped as mpirun ends
    for pid in $ours; do
        alive "$pid" && fail "process $pid of the session left behind: $(ps -o pid=,stat=,args= -p "$pid")"
    done
    echo "ok: $(grep 'stopped answering' view.log); closed with status $STATUS"
    ;;
scrub)
    # The film's frames as render writes them (the same pixels still and the window give).
    rm -rf film.mp4.frames film.mp4
    "$RAYFARM" render "$scene" --size $SIZE --spp 4 -o film.mp4 --frames-dir film.mp4.frames --overwrite 2>render.log ||
        fail "render: $(tail -2 render.log)"
    frames=(film.mp4.frames/frame_*.png)
    [ ${#frames[@]} -ge 8 ] || fail "the film has ${#frames[@]} frames"
    [ "$(differing "${frames[0]}" "${frames[$((${#frames[@]} / 2))]}")" != 0 ] || fail "frames 0 and the middle one look alike: no pose to scrub"
    start_view "$scene" --size $SIZE --spp 4
    wait_equal "${frames[0]}" 60 start
    # The slider runs along the window's foot, after the Play button: press on its handle (at
    # its left end, frame 0) and drag it right, as a user scrubs. The row is found by trying a
    # few heights above the status line (elsewhere the press lands on empty window).
    geo=$(xdotool getwindowgeometry --shell "$WID")
    eval "$geo"
    for y in $((HEIGHT - 32)) $((HEIGHT - 28)) $((HEIGHT - 36)) $((HEIGHT - 24)) $((HEIGHT - 40)); do
        xdotool mousemove --window "$WID" 93 $y mousedown 1
        for i in $(seq 10); do xdotool mousemove --window "$WID" $((93 + i * (WIDTH - 200) / 20)) $y; sleep 0.05; done
        xdotool mouseup 1
        sleep 1
        grab probe.png
        [ "$(differing probe.png "${frames[0]}")" != 0 ] && break
    done
    settle scrubbed
    match=
    for f in "${frames[@]}"; do
        [ "$(differing scrubbed.png "$f")" = 0 ] && { match=$f; break; }
    done
    [ -n "$match" ] || fail "after the scrub the window shows none of the film's frames (see $WORK/scrubbed.png)"
    [ "$match" != "${frames[0]}" ] || fail "the scrub left the window on frame 0"
    xdotool windowfocus --sync "$WID" key Home; wait_equal "${frames[0]}" 30 home
    close_view 5 view
    [ $STATUS -eq 0 ] || fail "view exited with status $STATUS: $(cat view.log)"
    echo "ok: scrubbing the timeline showed $(basename "$match") exactly, a pose other than frame 0's"
    ;;
interact)
    "$RAYFARM" still "$scene" --size $SIZE --spp 4 -o still.png 2>/dev/null || fail "still"
    "$RAYFARM" still "$scene" --size $SIZE --spp 4 --frame 1 -o still1.png 2>/dev/null || fail "still --frame 1"
    [ "$(differing still.png still1.png)" != 0 ] || fail "frames 0 and 1 of $scene look alike: no playback to see"
    start_view "$scene" --size $SIZE --spp 4
    wait_equal still.png 60 start
    # Each move changes the picture, R returns exactly to the timeline's camera.
    drag 2 "" pan_middle;  wait_equal still.png 30 reset_pan_middle
    drag 1 shift pan_shift; wait_equal still.png 30 reset_pan_shift
    drag 1 "" orbit;       wait_equal still.png 30 reset_orbit
    for p in pan_middle pan_shift; do [ "$(differing $p.png still.png)" != 0 ] || fail "$p did not change the picture"; done
    # Middle and shift drags are the same pan (up to rounding as motion events group
    # differently): PSNR ≥ 30 dB between them, and both far from an orbit of the same motion.
    close_pans=$(psnr pan_middle.png pan_shift.png)
    far=$(psnr pan_shift.png orbit.png)
    awk -v a="$close_pans" -v b="$far" 'BEGIN { exit !(a >= 30 && b < a) }' ||
        fail "middle vs shift pan: $close_pans dB; shift pan vs orbit: $far dB (a pan should be the pan)"
    xdotool mousemove --window "$WID" 80 45 click 4 click 4 click 4  # wheel: zoom in
    settle zoom
    [ "$(differing zoom.png still.png)" != 0 ] || fail "the wheel did not change the picture"
    xdotool key r; wait_equal still.png 30 reset_zoom
    # F frames the model: a new picture, the same one every time from the same camera.
    xdotool windowfocus --sync "$WID" key f; settle framed
    [ "$(differing framed.png still.png)" != 0 ] || fail "F did not change the picture"
    xdotool key r; wait_equal still.png 30 reset_framed
    xdotool key f; wait_equal framed.png 30 framed_again
    xdotool key r; wait_equal still.png 30 reset_framed2
    # T tints tiles by rank and T again removes the tint.
    xdotool key t; settle tinted
    [ "$(differing tinted.png still.png)" != 0 ] || fail "T did not tint the picture"
    xdotool key t; wait_equal still.png 30 untinted
    # The timeline: Right steps to frame 1 (still --frame 1 exactly); Space plays (the picture
    # keeps changing); Space pauses; Home returns to frame 0.
    xdotool key Right; wait_equal still1.png 30 frame1
    xdotool key space
    for i in $(seq 8); do grab play_$i.png; sleep 0.25; done
    xdotool key space
    distinct=$(md5sum play_*.png | cut -d' ' -f1 | sort -u | wc -l)
    [ "$distinct" -ge 4 ] || fail "playing showed $distinct different pictures in 2 s"
    xdotool key Home; wait_equal still.png 30 home
    close_view 5 view
    [ $STATUS -eq 0 ] || fail "view exited with status $STATUS: $(cat view.log)"
    echo "ok: middle/shift pan, orbit, wheel, F, R, T change or restore the picture; pans $close_pans dB apart; playback showed $distinct pictures"
    ;;
killed-rank-default)
    # As killed-rank, under mpirun's defaults: mpirun ends every rank as soon as one dies
    # (SIGTERM, then SIGKILL 1 s later); rank 0 must name the dead rank before it goes.
    [ -n "${VIEW_NP:-}" ] || fail "killed-rank-default runs under mpirun (VIEW_NP=3)"
    start_view "$scene" --size 320x180 --spp 1024
    sleep 1
    victim=
    for pid in $(descendants $VIEW); do
        [ "$(ps -o comm= -p "$pid")" = rayfarm ] && victim=$pid
    done
    [ -n "$victim" ] || fail "no rank found under mpirun"
    rank=$(tr '\0' '\n' </proc/"$victim"/environ | sed -n 's/^OMPI_COMM_WORLD_RANK=//p')
    [ -n "$rank" ] && [ "$rank" != 0 ] || fail "process $victim is not a worker rank (rank '$rank')"
    ours=$(descendants $VIEW)
    kill -9 "$victim"
    for _ in $(seq 100); do kill -0 $VIEW 2>/dev/null || break; sleep 0.05; done
    kill -0 $VIEW 2>/dev/null && fail "mpirun still runs 5 s after rank $rank died"
    wait $VIEW
    STATUS=$?
    VIEW=
    [ $STATUS -ne 0 ] || fail "a session that lost a rank exited 0"
    grep -q "^rayfarm: error: view: rank $rank stopped answering" view.log ||
        fail "rank 0 did not name the dead rank $rank: $(cat view.log)"
    [ "$(grep -c '^rayfarm: error: view:' view.log)" = 1 ] || fail "more than one error line: $(cat view.log)"
    sleep 1
    for pid in $ours; do
        alive "$pid" && fail "process $pid of the session left behind: $(ps -o pid=,stat=,args= -p "$pid")"
    done
    # The report outlives the job: a window of a process of its own names the dead rank over
    # the last picture until it is closed, and then nothing is left.
    WID=
    for _ in $(seq 50); do
        WID=$(xdotool search --name '^rayfarm view - stopped' 2>/dev/null | head -1)
        [ -n "$WID" ] && break
        sleep 0.2
    done
    [ -n "$WID" ] || fail "no window reports the dead rank once mpirun has ended the job: $(cat view.log)"
    report=$(xdotool getwindowpid "$WID")
    sleep 2  # it lasts
    check_stopped_banner "rank $rank stopped answering"
    xdotool windowfocus --sync "$WID" key ctrl+q
    for _ in $(seq 40); do alive "$report" || break; sleep 0.05; done
    alive "$report" && fail "the report window's process $report still runs 2 s after Ctrl+Q"
    echo "ok: $(grep '^rayfarm: error: view:' view.log); mpirun exited $STATUS; a report window showed it until closed"
    ;;
window-destroyed | display-lost)
    start_view "$scene" --size $SIZE --spp 4
    sleep 1  # rendering, and under mpirun the ranks at work
    ours=$(descendants $VIEW)
    if [ "$CASE" = window-destroyed ]; then
        xdotool windowclose "$WID"
        want="^rayfarm: error: view: the window was destroyed from outside (on display $DISPLAY); the session ends$"
    else
        kill -9 $XVFB
        wait $XVFB 2>/dev/null
        XVFB=
        want="^rayfarm: error: view: lost the connection to the display $DISPLAY (The X11 connection broke"
    fi
    for _ in $(seq 100); do kill -0 $VIEW 2>/dev/null || break; sleep 0.05; done
    kill -0 $VIEW 2>/dev/null && fail "the session still runs 5 s after its display went: $(cat view.log)"
    wait $VIEW
    STATUS=$?
    VIEW=
    [ $STATUS -ne 0 ] || fail "exit status 0 after the display went"
    [ -n "${VIEW_NP:-}" ] || [ $STATUS -eq 1 ] || fail "exit status $STATUS, expected 1: $(cat view.log)"
    grep -q "$want" view.log || fail "no line saying what happened: $(cat view.log)"
    [ "$(grep -c '^rayfarm: error:' view.log)" = 1 ] || fail "expected one error line: $(cat view.log)"
    sleep 1
    for pid in $ours; do
        alive "$pid" && fail "process $pid of the session left behind: $(ps -o pid=,stat=,args= -p "$pid")"
    done
    echo "ok: $CASE: $(grep '^rayfarm: error:' view.log); status $STATUS; no process left"
    ;;
*) fail "unknown case $CASE" ;;
esac
