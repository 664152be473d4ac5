#!/bin/bash
# A Cycles reference of a rayfarm scene file naming one OBJ, STL, PLY, FBX or COLLADA model,
# imported by Blender 3.4's own importer for its format: Blender (Debian's blender 3.4) in the
# background with factory settings, running assimp_cycles_reference.py. A developer tool: no
# test needs it.
#   tests/reference/assimp_cycles_reference.sh SCENE.json -o OUT.png [--samples 128] [--threads N]
# Runs under nice -n 19 (CYCLES_NICE=0 for timings).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
command -v blender >/dev/null || { echo "assimp_cycles_reference: blender not found (apt-get install blender)" >&2; exit 2; }
exec nice -n "${CYCLES_NICE:-19}" blender --background --factory-startup --python-exit-code 2 \
    --python "$here/assimp_cycles_reference.py" -- "$@"
