#!/usr/bin/env bash
# A glTF model to an MP4 turntable: a bare model gets the default turntable (camera framed on the
# model's bounds, one orbit in 4 s at 30 fps = 120 frames, a default light rig).
#   bash examples/turntable_mp4.sh [MODEL] [RANKS]
# Without mpirun (RANKS=0) it runs as one process on all cores; PNG frames are kept next to the
# video (out/engine_turntable.mp4.frames/) so an interrupted run can be resumed with --resume.
set -euo pipefail
cd "$(dirname "$0")/.."
model=${1:-/usr/share/assimp/models/glTF2/2CylinderEngine-glTF-Binary/2CylinderEngine.glb}
ranks=${2:-2}
source examples/common.sh
mkdir -p out
if [ "$ranks" -gt 0 ]; then
  mpirun --oversubscribe -np "$ranks" "$bin" render "$model" -o out/engine_turntable.mp4 --size 640x360 --stats out/engine_turntable.json --overwrite
else
  "$bin" render "$model" -o out/engine_turntable.mp4 --size 640x360 --stats out/engine_turntable.json --overwrite
fi
ffprobe -v error -select_streams v:0 -show_entries stream=codec_name,width,height,r_frame_rate,nb_frames,pix_fmt \
  -of default=nw=1 out/engine_turntable.mp4 || true
echo "turntable_mp4: wrote out/engine_turntable.mp4 (stats: out/engine_turntable.json)"
