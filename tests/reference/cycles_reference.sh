#!/bin/bash
# A Cycles reference of a glTF file: Blender (Debian packages blender 3.4 and python3-numpy, which
# its glTF importer needs) in the background with factory settings, running cycles_reference.py.
# A developer tool: no test needs it.
#   tests/reference/cycles_reference.sh MODEL.gltf -o OUT.png [--size 320x180] [--samples 256]
#       [--camera N] [--environment FILE.exr] [--environment-strength K] [--bounces N] [--threads N]
#       [--multiscatter]
# Everything after the model goes to the script (see its --help). Runs under nice -n 19
# (CYCLES_NICE=0 for timings).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
command -v blender >/dev/null || { echo "cycles_reference: blender not found (apt-get install blender python3-numpy)" >&2; exit 2; }
exec nice -n "${CYCLES_NICE:-19}" blender --background --factory-startup --python-exit-code 2 \
    --python "$here/cycles_reference.py" -- "$@"
