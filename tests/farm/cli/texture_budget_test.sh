#!/usr/bin/env bash
# Issue 29: the texture budget, end to end. A small PNG that declares 16384x16384 (grey, all
# zero: about a quarter of a megabyte) on BoxTextured renders with it downsampled to 8192 (a note
# says so) within 2 GB of peak memory (/usr/bin/time's maximum resident set), at the default
# --exposure auto as well (the meter's copy of the scene shares its textures); --max-texture-size
# shrinks it further; report --reference refuses such an image from its header, in one line.
# Prints the figures. Usage: texture_budget_test.sh RAYFARM WORK_DIR
set -euo pipefail
RAYFARM=$1 WORK=$2
HERE=$(cd "$(dirname "$0")" && pwd)
SRC=/usr/share/assimp/models/glTF2/BoxTextured-glTF
fail() { echo "FAIL: $*" >&2; exit 1; }
[ -x /usr/bin/time ] || fail "/usr/bin/time missing (package time)"
rm -rf "$WORK"
mkdir -p "$WORK"
cd "$WORK"
cp "$SRC/BoxTextured0.bin" .
python3 "$HERE/../data/big_inputs.py" png-bomb 16384 bomb.png bomb.gltf
bytes=$(stat -c %s bomb.png)
[ "$bytes" -lt 1000000 ] || fail "the bomb PNG is $bytes bytes, not small"

# 1. Downsampled to 8192 on load, under 2 GB.
/usr/bin/time -f '%M %e' -o time.txt "$RAYFARM" still bomb.gltf -o bomb_still.png --size 64x48 --spp 1 --exposure 0 2>err.txt \
    || fail "still failed: $(cat err.txt)"
read -r kb secs <time.txt
grep -q 'images\[0\] "bomb.png": 16384x16384 downsampled to 8192x8192 on load' err.txt || fail "no downsampling note: $(cat err.txt)"
[ "$kb" -lt 2000000 ] || fail "peak memory $kb KB, over 2 GB"
echo "texture_budget: ${bytes}-byte PNG declaring 16384x16384: still in ${secs} s, peak ${kb} KB (limit 2000000)"

# 1b. The same at the default --exposure auto: the meter's probe scene shares the textures.
/usr/bin/time -f '%M %e' -o time.txt "$RAYFARM" still bomb.gltf -o bomb_auto.png --size 64x48 --spp 1 2>err.txt \
    || fail "still (auto exposure) failed: $(cat err.txt)"
read -r kba secsa <time.txt
grep -q 'auto exposure' err.txt || fail "no auto exposure line: $(cat err.txt)"
[ "$kba" -lt 2000000 ] || fail "peak memory at --exposure auto $kba KB, over 2 GB"
echo "texture_budget: the same at --exposure auto: ${secsa} s, peak ${kba} KB (limit 2000000)"

# 2. --max-texture-size 1024: a smaller texture, a smaller peak.
/usr/bin/time -f '%M %e' -o time.txt "$RAYFARM" still bomb.gltf -o small.png --size 64x48 --spp 1 --exposure 0 --max-texture-size 1024 2>err.txt \
    || fail "still --max-texture-size 1024 failed: $(cat err.txt)"
read -r kb2 secs2 <time.txt
grep -q 'downsampled to 1024x1024' err.txt || fail "no 1024 note: $(cat err.txt)"
[ "$kb2" -lt "$kb" ] || fail "--max-texture-size 1024 peaked at $kb2 KB, not below $kb KB"
echo "texture_budget: --max-texture-size 1024: ${secs2} s, peak ${kb2} KB"

# 3. report --reference refuses the bomb from its header, in one line, exit 2.
set +e
"$RAYFARM" report bomb.gltf --reference bomb.png --out rep 2>err.txt >/dev/null
status=$?
set -e
[ "$status" -eq 2 ] || fail "report --reference bomb.png: exit $status, expected 2: $(cat err.txt)"
errs=$(grep -v '^rayfarm: note:' err.txt)
[ "$(printf '%s\n' "$errs" | wc -l)" -eq 1 ] || fail "expected one error line, got: $errs"
case "$errs" in *"declares 16384x16384, over 8192 on a side (--max-texture-size)"*) ;; *) fail "unexpected message: $errs" ;; esac
echo "texture_budget: ok"
