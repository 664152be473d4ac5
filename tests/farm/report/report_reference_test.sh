#!/usr/bin/env bash
# rayfarm report --reference end to end, through the real binary: a reference equal to one
# render (a rayfarm still of pbr_grid through its glTF camera, exposure 0, clamp) scores that
# setting PSNR inf and SSIM 1; the other settings and a reference at another exposure score lower;
# the render follows the reference's size; a bad reference (missing, not an image, truncated, or
# another size than --size) is one error line, exit status 2, and no report.
set -u
rayfarm=$1 src=$2 out=$3
model=$src/scenes/pbr_grid/pbr_grid.gltf
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }
pic=(--camera 0 --exposure 0 --tonemap clamp)
sweep=(--no-video --spp 1 --depth 5 --min-weight 0.001 --indirect 0 --sweep-spp 1,4 --sweep-depth 5
       --sweep-min-weight 0.001 --sweep-indirect 0)

# The CSV cell of the row whose first cells are "factor,spp" in column NAME.
cell() {  # file factor spp name
  awk -F, -v f="$2" -v s="$3" -v n="$4" 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
    $c["factor"] == f && $c["spp"] == s { print $c[n] }' "$1"
}

"$rayfarm" still "$model" "${pic[@]}" --spp 1 --size 64x36 -o "$out/still.png" 2>/dev/null || fail "still"
"$rayfarm" report "$model" "${pic[@]}" "${sweep[@]}" --reference "$out/still.png" --out "$out/same" \
  2>"$out/same.log" || fail "report --reference: $(cat "$out/same.log")"
csv=$out/same/report.csv
[ "$(cell "$csv" default 1 psnr_db)" = inf ] || fail "the setting the reference was rendered at: PSNR $(cell "$csv" default 1 psnr_db), not inf"
[ "$(cell "$csv" default 1 ssim)" = 1 ] || fail "the setting the reference was rendered at: SSIM $(cell "$csv" default 1 ssim), not 1"
psnr4=$(cell "$csv" spp 4 psnr_db) ssim4=$(cell "$csv" spp 4 ssim)
awk -v p="$psnr4" -v s="$ssim4" 'BEGIN { exit !(p != "inf" && p + 0 > 10 && s + 0 < 1) }' ||
  fail "spp 4 against the 1-spp still: PSNR $psnr4, SSIM $ssim4 (want finite and below 1)"
[ -e "$out/same/reference.png" ] && fail "an external reference was copied or rendered as reference.png"
grep -q "an image made elsewhere" "$out/same/summary.md" || fail "summary.md does not name the external reference"
[ -s "$out/same/error_vs_time.png" ] || fail "no plot"

# The indirect-light knob is swept too, and changes the picture.
"$rayfarm" report "$model" "${pic[@]}" "${sweep[@]}" --sweep-spp 1 --sweep-indirect 0,1 --reference "$out/still.png" \
  --out "$out/indirect" 2>"$out/indirect.log" || fail "report --sweep-indirect 0,1: $(cat "$out/indirect.log")"
ind=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) c[$i] = i; next }
  $c["factor"] == "indirect" && $c["indirect_samples"] == 1 { print $c["psnr_db"] }' "$out/indirect/report.csv")
[ -n "$ind" ] && [ "$ind" != inf ] || fail "indirect 1 against the indirect-0 still: PSNR '$ind' (want a finite score)"

# Another picture (one stop brighter) scores lower, and a reference of another size sets the size.
"$rayfarm" still "$model" --camera 0 --exposure 1 --tonemap clamp --spp 1 --size 48x27 -o "$out/bright.png" \
  2>/dev/null || fail "still --exposure 1"
"$rayfarm" report "$model" "${pic[@]}" "${sweep[@]}" --reference "$out/bright.png" --out "$out/bright" \
  2>"$out/bright.log" || fail "report against bright.png: $(cat "$out/bright.log")"
awk -v p="$(cell "$out/bright/report.csv" default 1 psnr_db)" -v s="$(cell "$out/bright/report.csv" default 1 ssim)" \
  'BEGIN { exit !(p != "inf" && p + 0 < 30 && s + 0 < 0.99) }' || fail "a brighter reference scores as well as an equal one"
size=$(python3 -c 'import struct,sys; d=open(sys.argv[1],"rb").read(24); print("%dx%d" % struct.unpack(">II", d[16:24]))' \
  "$out/bright/default.png")
[ "$size" = 48x27 ] || fail "the render did not take the reference's size 48x27: $size"

# Bad references: one line, exit 2, nothing written.
printf 'not a png' > "$out/text.png"
head -c 200 "$out/still.png" > "$out/truncated.png"
for case in "missing.png" "text.png" "truncated.png" "still.png --size 32x18"; do
  set -- $case
  ref=$out/$1
  shift
  err=$("$rayfarm" report "$model" "${pic[@]}" "${sweep[@]}" --reference "$ref" "$@" --out "$out/bad" 2>&1 >/dev/null |
        grep -v '^rayfarm: note:'; exit "${PIPESTATUS[0]}")
  status=$?
  [ $status -eq 2 ] || fail "$case: exit status $status, not 2 ($err)"
  [ "$(printf '%s\n' "$err" | wc -l)" -eq 1 ] || fail "$case: expected one error line, got: $err"
  case "$err" in "rayfarm: error: $ref: "*) ;; *) fail "$case: unexpected message: $err" ;; esac
  [ -e "$out/bad/report.csv" ] && fail "$case wrote a report"
done
echo "ok"
