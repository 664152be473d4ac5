#!/usr/bin/env bash
# Issue 46 #6: glTF lights and IORs that a scene file would refuse (negative intensity, an
# inner cone past the outer one, range 0, a negative colour, IOR -1.5) are refused by render and
# still: exit 2, one line naming the file, the light or material and the value; nothing written.
# Usage: gltf_values_test.sh RAYFARM WORK_DIR
set -euo pipefail
RAYFARM=$1 WORK=$2
BOX=/usr/share/assimp/models/glTF2/BoxTextured-glTF
rm -rf "$WORK"
mkdir -p "$WORK"
cd "$WORK"
cp "$BOX"/* .

. "$(dirname "$0")/../../lib/refusal.sh"  # fail, expect_refusal
# variant NAME 'LIGHT JSON' ['MATERIAL EXTENSIONS JSON']: BoxTextured lit by LIGHT, as NAME.gltf.
variant() {
    python3 - "$1" "$2" "${3:-}" <<'PY'
import json, sys
name, light, ext = sys.argv[1], json.loads(sys.argv[2]), sys.argv[3]
g = json.load(open("BoxTextured.gltf"))
g["nodes"].append({"translation": [0, 3, 3], "extensions": {"KHR_lights_punctual": {"light": 0}}})
g["scenes"][0]["nodes"].append(len(g["nodes"]) - 1)
g.setdefault("extensionsUsed", []).append("KHR_lights_punctual")
g.setdefault("extensions", {})["KHR_lights_punctual"] = {"lights": [light]}
if ext:
    g["materials"][0].setdefault("extensions", {}).update(json.loads(ext))
    g["extensionsUsed"].append("KHR_materials_ior")
json.dump(g, open(name + ".gltf", "w"))
PY
}

variant ok '{"type": "spot", "name": "Key", "intensity": 50, "range": 20, "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}}'
"$RAYFARM" still ok.gltf --size 32x24 -o ok.png 2> ok.log || { cat ok.log; fail "a valid light was refused"; }

variant intensity '{"type": "point", "name": "Key", "intensity": -5}'
variant cone '{"type": "spot", "name": "Key", "spot": {"innerConeAngle": 0.6, "outerConeAngle": 0.3}}'
variant range '{"type": "point", "name": "Key", "range": 0}'
variant colour '{"type": "point", "name": "Key", "color": [1, -1, 1]}'
variant ior '{"type": "point", "intensity": 10}' '{"KHR_materials_ior": {"ior": -1.5}}'
L='KHR_lights_punctual.lights[0] ("Key")'
expect_refusal "intensity.gltf: $L.intensity -5: expected a number ≥ 0" "$RAYFARM" still intensity.gltf --size 32x24 -o x.png
expect_refusal "cone.gltf: $L.spot.innerConeAngle 0.6: must not exceed outerConeAngle 0.3" "$RAYFARM" still cone.gltf --size 32x24 -o x.png
expect_refusal "range.gltf: $L.range 0: expected a positive distance" "$RAYFARM" still range.gltf --size 32x24 -o x.png
expect_refusal "colour.gltf: $L.color [1, -1, 1]: colour components must be ≥ 0" \
    "$RAYFARM" render colour.gltf --size 32x24 --frames 0:1 -o x.mp4
material=$(python3 -c 'import json; m = json.load(open("ior.gltf"))["materials"][0]; print(m.get("name", ""))')
expect_refusal "ior.gltf: materials[0]${material:+ (\"$material\")}.extensions.KHR_materials_ior.ior -1.5: expected an index of refraction of 1 or more" \
    "$RAYFARM" render ior.gltf --size 32x24 --frames 0:1 -o y.mp4
for f in x.png x.mp4 x.mp4.frames y.mp4 y.mp4.frames; do [ ! -e "$f" ] || fail "a refused run left $f"; done
echo "gltf values: out-of-range lights and IOR refused with exit 2 naming light or material and value"
