#!/usr/bin/env bash
# Issue 47 #6: outputs create their folders, as Blender does: -o (plain and templated, with one
# scene and several), --frames-dir, --stats, --contact-sheet, --poster, still's -o and --stats;
# under mpirun too. A folder that cannot be made is refused before rendering, naming it.
#   output_folders_test.sh RAYFARM SOURCE_DIR OUT_DIR
set -euo pipefail
rayfarm=$1 src=$2 out=$3
# shellcheck source=tests/lib/refusal.sh
source "$src/tests/lib/refusal.sh"
rm -rf "$out" && mkdir -p "$out" && cd "$out"
scene=$src/scenes/whitted.json
small=(--size 32x18 --frames 0:1)

# The README's own example, with one scene and with two: out/{name}.mp4 into a missing out/.
"$rayfarm" render "$scene" -o 'one/{name}.mp4' "${small[@]}" 2>one.log || { cat one.log; fail "templated -o with one scene"; }
[ -s one/whitted.mp4 ] && [ -d one/whitted.mp4.frames ] || fail "one/whitted.mp4 and its frames: $(ls -R one)"
cp "$scene" a.json && cp "$scene" b.json
"$rayfarm" render a.json b.json -o 'films/{name}.mp4' "${small[@]}" 2>two.log || { cat two.log; fail "templated -o with two scenes"; }
[ -s films/a.mp4 ] && [ -s films/b.mp4 ] || fail "films/a.mp4 and films/b.mp4: $(ls -R films)"

# Every output of a render into folders that are not there yet.
"$rayfarm" render "$scene" -o deep/er/film.mp4 "${small[@]}" --frames-dir kept/x/frames --stats stats/run.json \
    --contact-sheet sheets/s.png --poster posters/p.png 2>all.log || { cat all.log; fail "every output in new folders"; }
for f in deep/er/film.mp4 kept/x/frames/frame_000000.png stats/run.json sheets/s.png posters/p.png; do
    [ -s "$f" ] || fail "$f was not written: $(cat all.log)"
done
"$rayfarm" still "$scene" --size 32x18 -o stills/one.png --stats stills/stats/one.json 2>still.log || { cat still.log; fail "still into new folders"; }
[ -s stills/one.png ] && [ -s stills/stats/one.json ] || fail "still's outputs: $(ls -R stills)"

# Under mpirun: rank 0 makes the folders, the film is whole.
if command -v mpirun >/dev/null; then
    mpirun --oversubscribe -np 2 "$rayfarm" render "$scene" -o 'mpi/{name}.mp4' "${small[@]}" --mode frame 2>mpi.log ||
        { cat mpi.log; fail "mpirun -np 2 into a new folder"; }
    [ -s mpi/whitted.mp4 ] || fail "mpi/whitted.mp4 was not written"
fi

# Each output its own frames folder: a.webm and a.gif of one stem do not share one (the second
# run was refused when both were a.frames), and --resume finds each output's own.
"$rayfarm" render "$scene" -o a.webm "${small[@]}" 2>a1.log || { cat a1.log; fail "a.webm"; }
"$rayfarm" render "$scene" -o a.gif "${small[@]}" 2>a2.log || { cat a2.log; fail "a.gif after a.webm of the same stem: $(cat a2.log)"; }
[ -s a.webm.frames/frame_000001.png ] && [ -s a.gif.frames/frame_000001.png ] || fail "a.webm.frames and a.gif.frames: $(ls)"
[ ! -e a.frames ] || fail "a.frames was made"
rm a.gif.frames/frame_000001.png
"$rayfarm" render "$scene" -o a.gif "${small[@]}" --resume 2>a3.log || { cat a3.log; fail "resume of a.gif"; }
grep -q "1 of 2 frames kept in a.gif.frames, 1 to render" a3.log || fail "resume of a.gif did not use a.gif.frames: $(cat a3.log)"

# A folder that cannot be made: a file in the way, for each output; nothing rendered, no folder
# left half made.
touch blocker
expect_refusal --exact "blocker: cannot create the folder for blocker/film.mp4: blocker is a file, not a folder" \
    "$rayfarm" render "$scene" -o blocker/film.mp4 "${small[@]}"
expect_refusal --exact "blocker/sub: cannot create the folder for blocker/sub/film.mp4: blocker is a file, not a folder" \
    "$rayfarm" render "$scene" -o blocker/sub/film.mp4 "${small[@]}"
expect_refusal --prefix "blocker: cannot create the folder for blocker/s.json" \
    "$rayfarm" render "$scene" -o ok.mp4 "${small[@]}" --stats blocker/s.json
expect_refusal --prefix "blocker: cannot create the folder for blocker/frames" \
    "$rayfarm" render "$scene" -o ok2.mp4 "${small[@]}" --frames-dir blocker/frames
expect_refusal --exact "blocker: cannot create the folder for blocker/one.png: blocker is a file, not a folder" \
    "$rayfarm" still "$scene" --size 32x18 -o blocker/one.png
[ ! -e ok.mp4 ] && [ ! -e ok2.mp4 ] || fail "a refused render left its video"
echo "output folders: all passed"
