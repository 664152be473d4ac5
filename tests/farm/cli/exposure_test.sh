#!/usr/bin/env bash
# --exposure end to end: auto exposure (the glTF default) is metered once per film, so every
# frame of a turntable (and a still of any of them) gets the same EV; a fixed EV skips the
# meter; a bad value is one error line and exit status 2.
set -u
rayfarm=$1 out=$2
model=/usr/share/assimp/models/glTF2/BoxTextured-glTF-Binary/BoxTextured.glb
mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }
[ -f "$model" ] || fail "$model missing (package assimp-testmodels)"

ev_of() { grep -o 'auto exposure: EV [-+0-9.]*' | sed 's/.*EV //'; }
ev0=$("$rayfarm" still "$model" --size 64x36 -o "$out/f0.png" --frame 0 2>&1 | ev_of)
ev45=$("$rayfarm" still "$model" --size 64x36 -o "$out/f45.png" --frame 45 2>&1 | ev_of)
[ -n "$ev0" ] || fail "still of a glTF model printed no auto exposure"
[ "$ev0" = "$ev45" ] || fail "frames 0 and 45 metered differently: $ev0 vs $ev45"
cmp -s "$out/f0.png" "$out/f45.png" && fail "frames 0 and 45 are the same picture (the turntable did not turn)"

log=$("$rayfarm" render "$model" --size 64x36 --frames 0:3 -o "$out/t.mp4" --no-frames 2>&1) || fail "render: $log"
[ "$(printf '%s\n' "$log" | grep -c 'auto exposure: EV')" -eq 1 ] || fail "render metered other than once: $log"
[ "$(printf '%s\n' "$log" | ev_of)" = "$ev0" ] || fail "render and still chose different EVs"

"$rayfarm" still "$model" --size 64x36 -o "$out/fixed.png" --exposure 1.5 2>&1 | grep -q 'auto exposure' &&
  fail "--exposure 1.5 still metered"
for bad in "--exposure bright" "--exposure 99" "--tonemap filmic"; do
  err=$("$rayfarm" still "$model" $bad --size 64x36 -o "$out/bad.png" 2>&1 >/dev/null)
  status=$?
  [ $status -eq 2 ] || fail "$bad: exit status $status, not 2"
  [ "$(printf '%s\n' "$err" | wc -l)" -eq 1 ] || fail "$bad: expected one error line, got: $err"
  case "$err" in "rayfarm: error: "*) ;; *) fail "$bad: unexpected message: $err" ;; esac
done
# A file with its own dim light (scenes/dim_light: one 10 cd point lamp): auto exposure meters
# it lit and the default --min-weight keeps its light (mean luma above 25 of 255; it was 0.3
# when pruning compared radiance before exposure). The same file with the lamp at 0 cd says so
# in one warning line naming the lamp and its unit.
dim=$(cd "$(dirname "$0")/../../../scenes/dim_light" && pwd)/dim_light.gltf
luma() { ffmpeg -v error -i "$1" -vf signalstats,metadata=mode=print:file=- -f null - 2>&1 | sed -n 's/.*YAVG=//p' | head -1; }
log=$("$rayfarm" still "$dim" --camera 0 --size 160x90 -o "$out/dim.png" 2>&1) || fail "dim light: $log"
printf '%s\n' "$log" | grep -q warning && fail "dim light: unexpected warning: $log"
y=$(luma "$out/dim.png")
awk -v y="$y" 'BEGIN { exit !(y > 25) }' || fail "dim light rendered dark: mean luma $y"
sed 's/"intensity": 10.0/"intensity": 0.0/' "$dim" > "$out/dark.gltf"
log=$("$rayfarm" still "$out/dark.gltf" --camera 0 --size 160x90 -o "$out/dark.png" 2>&1) || fail "dark: $log"
[ "$(printf '%s\n' "$log" | grep -c '^rayfarm: warning: ')" -eq 1 ] || fail "dark file: expected one warning line: $log"
printf '%s\n' "$log" | grep -q '^rayfarm: warning: auto exposure: the metered frames hold no light at all; lights: lamp (point, 0 cd)$' ||
  fail "dark file: warning does not name the lamp and its unit: $log"
# --environment: Blender's DWAB studio loads; a truncated, over-size or missing file is one
# line, exit 2.
studio=$(cd "$(dirname "$0")/../../../scenes/environments" && pwd)/studio.exr
"$rayfarm" still "$model" --size 64x36 -o "$out/env.png" --environment "$studio" --environment-rotation 90 \
  --environment-intensity 0.5 2>/dev/null || fail "--environment studio.exr"
head -c 40000 "$studio" > "$out/truncated.exr"
printf '#?RADIANCE\nFORMAT=32-bit_rle_rgbe\n\n-Y 90000 +X 90000\n' > "$out/huge.hdr"
for bad in "$out/truncated.exr" "$out/huge.hdr" "$out/missing.exr"; do
  err=$("$rayfarm" still "$model" --environment "$bad" --size 64x36 -o "$out/bad.png" 2>&1 >/dev/null)
  status=$?
  [ $status -eq 2 ] || fail "--environment $bad: exit status $status, not 2"
  [ "$(printf '%s\n' "$err" | wc -l)" -eq 1 ] || fail "--environment $bad: expected one error line, got: $err"
  case "$err" in "rayfarm: error: $bad: "*) ;; *) fail "--environment $bad: unexpected message: $err" ;; esac
done
echo "ok"
