#!/usr/bin/env bash
# rayfarm info MODEL --json against golden JSON written by hand from each file's contents
# (tests/farm/data/info/*.json: assimp's simple_skin, AnimatedMorphCube, BoxTextured and
# 2CylinderEngine, the project's textured_spot, the Blender walker and a variants file), the text form, the
# comparator shown able to fail, and bad input refused in one line with exit 2.
#   info_test.sh RAYFARM SOURCE_DIR OUT_DIR
set -u
rayfarm=$1 src=$2 out=$3
data=$src/tests/farm/data/info
assimp=/usr/share/assimp/models/glTF2
golden=$src/tests/farm/commands/info_golden.py
rm -rf "$out" && mkdir -p "$out"
fail=0
bad() { echo "FAIL: $*"; fail=1; }

check() {  # name model
    local name=$1 model=$2
    if [ ! -f "$model" ]; then bad "$name: $model is missing (assimp-testmodels)"; return; fi
    if ! "$rayfarm" info --json "$model" > "$out/$name.json" 2> "$out/$name.err"; then
        bad "$name: rayfarm info --json exited $?: $(head -1 "$out/$name.err")"; return
    fi
    if python3 "$golden" "$data/$name.json" "$out/$name.json" > "$out/$name.diff"; then
        echo "ok: $name matches its golden JSON"
    else
        bad "$name: differs from $data/$name.json:"; cat "$out/$name.diff"
    fi
    # What cannot be written by hand (the silhouette fit's distance) must at least be a distance.
    python3 - "$out/$name.json" <<'PY' || bad "$name: turntable camera distance not positive"
import json, sys
d = json.load(open(sys.argv[1]))["turntable"]["camera"]["distance"]
sys.exit(0 if d > 0 else 1)
PY
}

check simple_skin "$assimp/simple_skin/simple_skin.gltf"
check AnimatedMorphCube "$assimp/glTF-Sample-Models/AnimatedMorphCube-glTF/AnimatedMorphCube.gltf"
check BoxTextured "$assimp/BoxTextured-glTF/BoxTextured.gltf"
check 2CylinderEngine "$assimp/2CylinderEngine-glTF-Binary/2CylinderEngine.glb"
check textured_spot "$src/tests/reference/textured_spot.gltf"
check variants "$data/variants.gltf"
check walker "$src/tests/reference/characters/walker.gltf"

# The comparator fails on a wrong value: simple_skin's golden with 9 triangles.
python3 - "$data/simple_skin.json" "$out/wrong_golden.json" <<'PY'
import json, sys
g = json.load(open(sys.argv[1])); g["meshes"][0]["triangles"] = 9
json.dump(g, open(sys.argv[2], "w"))
PY
if python3 "$golden" "$out/wrong_golden.json" "$out/simple_skin.json" > /dev/null; then bad "the comparator passed a wrong golden"; fi

# The text form says the same.
"$rayfarm" info "$assimp/simple_skin/simple_skin.gltf" > "$out/simple_skin.txt" 2>&1 || bad "text form exited $?"
for want in "8 triangles drawn" "skins (1):" "0 (no name): 2 joints" "5.5 s, 1 channels (rotation)" \
            "165 frames at 30 fps" "skinned"; do
    grep -qF "$want" "$out/simple_skin.txt" || bad "text form lacks \"$want\""
done
"$rayfarm" info "$data/variants.gltf" > "$out/variants.txt" 2>&1 || bad "variants text form exited $?"
grep -qF '2 "matte black"' "$out/variants.txt" || bad "text form lacks the variant names"
grep -qF 'KHR_materials_anisotropy: not supported' "$out/variants.txt" || bad "text form does not say anisotropy is unsupported"

# --animation picks the turntable's clip; one the file lacks is refused, listing what it has.
"$rayfarm" info --json --animation 0 "$assimp/simple_skin/simple_skin.gltf" > /dev/null 2>&1 || bad "--animation 0 refused"

refused() {  # what expected-text args...
    local what=$1 want=$2; shift 2
    "$rayfarm" info "$@" > "$out/refused.out" 2> "$out/refused.err"
    local rc=$?
    local lines
    lines=$(wc -l < "$out/refused.err")
    if [ "$rc" -ne 2 ] || [ "$lines" -ne 1 ] || ! grep -q "^rayfarm: error: .*$want" "$out/refused.err" || [ -s "$out/refused.out" ]; then
        bad "$what: exit $rc, $lines stderr lines, want exit 2 and one line with \"$want\": $(cat "$out/refused.err")"
    else
        echo "ok: $what refused: $(cat "$out/refused.err")"
    fi
}
refused "a missing file" "no-such.gltf" "$out/no-such.gltf"
refused "an index out of range" "IndexOutOfRange" "$assimp/IndexOutOfRange/IndexOutOfRange.gltf"
refused "a glTF 1.0 file" "glTF 1" "$(ls /usr/share/assimp/models/glTF/*/*.gltf 2>/dev/null | head -1)"
refused "a scene file" "info describes a model: glTF" "$src/scenes/whitted.json"
refused "an unknown animation" "no animation named" --animation walk "$assimp/simple_skin/simple_skin.gltf"
refused "an unknown option" "--frobnicate" --frobnicate "$data/variants.gltf"
refused "no model" "expected one MODEL"
python3 - "$data/variants.gltf" "$out/required.gltf" <<'PY'
import json, sys
d = json.load(open(sys.argv[1])); d["extensionsRequired"] = ["KHR_materials_anisotropy"]
json.dump(d, open(sys.argv[2], "w"))
PY
refused "a required extension rayfarm lacks" "KHR_materials_anisotropy" "$out/required.gltf"

[ "$fail" -eq 0 ] && echo "info: all passed"
exit "$fail"
