#!/usr/bin/env bash
# A scene with a keyframed camera (scenes/flight.json: a Catmull-Rom camera path, an eased field
# of view and a moving coloured light) rendered to MP4 on an MPI farm.
#   bash examples/keyframed_camera.sh [RANKS]
set -euo pipefail
cd "$(dirname "$0")/.."
ranks=${1:-2}
source examples/common.sh
mkdir -p out
mpirun --oversubscribe -np "$ranks" "$bin" render scenes/flight.json -o out/flight.mp4 --stats out/flight.json --overwrite
echo "keyframed_camera: wrote out/flight.mp4; PNG frames in out/flight.mp4.frames/"
