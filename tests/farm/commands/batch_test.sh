#!/usr/bin/env bash
# Issue 32: many films in one job, `rayfarm render A B C -o 'out/{name}.mp4'`.
#   1. three models in one job, at 1 and at 3 ranks, give the same files (videos byte for byte,
#      PNG frames) as three separate runs;
#   2. a broken model among them fails alone: one error line naming it, the others written and
#      identical, the job's summary names it, exit status non-zero;
#   3. --resume applies film by film: one film missing frames renders only those, one never
#      started renders whole, and every file is again the separate runs';
#   4. several scenes with an -o that cannot tell the films apart is refused up front.
# Usage: batch_test.sh RAYFARM SOURCE_DIR WORK_DIR
set -euo pipefail
RAYFARM=$1 SRC=$2 WORK=$3
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1
M=/usr/share/assimp/models/glTF2
A=$M/BoxTextured-glTF/BoxTextured.gltf B=$M/BoxTexcoords-glTF/boxTexcoords.gltf C=$M/simple_skin/simple_skin.gltf
BROKEN=$M/IndexOutOfRange/IndexOutOfRange.gltf
rm -rf "$WORK" && mkdir -p "$WORK"
cd "$WORK"
fail() { echo "FAIL: $*" >&2; exit 1; }
mpi() { local np=$1; shift; mpirun --oversubscribe -np "$np" "$RAYFARM" "$@"; }
opts=(--size 64x48 --frames 0:7 --spp 1 --chunk-frames 4)
pngs_md5() { (cd "$1" && md5sum frame_*.png); }
same_as_separate() {  # dir names...
    local dir=$1 name
    shift
    for name in "$@"; do
        cmp -s "sep/$name.mp4" "$dir/$name.mp4" || fail "$dir/$name.mp4 differs from the separate run's"
        cmp -s <(pngs_md5 "sep/$name.mp4.frames") <(pngs_md5 "$dir/$name.mp4.frames") || fail "$dir/$name.mp4.frames differ from the separate run's"
    done
}

mkdir -p sep job1 job3 bad
for m in "$A" "$B" "$C"; do
    name=$(basename "$m" .gltf)
    "$RAYFARM" render "$m" "${opts[@]}" -o "sep/$name.mp4" 2> "sep_$name.log" || { cat "sep_$name.log"; fail "separate run of $name failed"; }
done
for np in 1 3; do
    mpi "$np" render "$A" "$B" "$C" "${opts[@]}" -o "job$np/{name}.mp4" --mode frame 2> "job$np.log" || { cat "job$np.log"; fail "job at np $np failed"; }
    same_as_separate "job$np" BoxTextured boxTexcoords simple_skin
    grep -q "^rayfarm: film 2 of 3: $B -> job$np/boxTexcoords.mp4$" "job$np.log" || { cat "job$np.log"; fail "no line for film 2 of 3"; }
    grep -q "^rayfarm: job of 3 films: 3 written$" "job$np.log" || { cat "job$np.log"; fail "no summary line"; }
done
echo "batch: three models in one job at np 1 and np 3: the same files as three separate runs"

set +e
mpi 3 render "$A" "$BROKEN" "$C" "${opts[@]}" -o "bad/{name}.mp4" 2> bad.log
rc=$?
set -e
[ "$rc" -ne 0 ] || { cat bad.log; fail "a job with a broken model exited 0"; }
[ "$(grep -c 'rayfarm: error' bad.log)" = 1 ] || { cat bad.log; fail "expected exactly one error line"; }
grep -q "^rayfarm: error: .*IndexOutOfRange.gltf" bad.log || { cat bad.log; fail "the error does not name the broken model"; }
grep -q "^rayfarm: job of 3 films: 2 written; failed: $BROKEN$" bad.log || { cat bad.log; fail "the summary does not name the failed film"; }
same_as_separate bad BoxTextured simple_skin
[ ! -e bad/IndexOutOfRange.mp4 ] || fail "the broken model left a video"
echo "batch: a broken model failed alone (exit $rc): $(grep 'rayfarm: error' bad.log | cut -c1-110)"

rm job3/BoxTextured.mp4 job3/BoxTextured.mp4.frames/frame_000002.png job3/BoxTextured.mp4.frames/frame_000005.png
rm -r job3/simple_skin.mp4 job3/simple_skin.mp4.frames
mpi 3 render "$A" "$B" "$C" "${opts[@]}" -o "job3/{name}.mp4" --resume 2> resume.log || { cat resume.log; fail "resumed job failed"; }
grep -q "resume: 6 of 8 frames kept in job3/BoxTextured.mp4.frames, 2 to render" resume.log || { cat resume.log; fail "film 1 did not resume its 2 missing frames"; }
grep -q "resume: 8 of 8 frames kept in job3/boxTexcoords.mp4.frames, 0 to render" resume.log || { cat resume.log; fail "film 2 did not keep its frames"; }
grep -q "job3/simple_skin.mp4.frames: nothing kept for this film yet; rendering it whole" resume.log || { cat resume.log; fail "film 3 was not started whole"; }
same_as_separate job3 BoxTextured boxTexcoords simple_skin
echo "batch: --resume film by film (2 missing frames, none missing, a film never started): the same files"

set +e
err=$("$RAYFARM" render "$A" "$B" "${opts[@]}" -o same.mp4 2>&1 >/dev/null)
rc=$?
set -e
[ "$rc" = 2 ] && [ "$(printf '%s\n' "$err" | wc -l)" = 1 ] || fail "-o without {name}: exit $rc, $err"
case "$err" in "rayfarm: error: -o same.mp4: with 2 scenes, it must hold {name}"*) ;; *) fail "-o without {name}: $err" ;; esac
[ ! -e same.mp4 ] || fail "a refused job wrote a file"
echo "batch: several scenes into one -o refused: $err"
